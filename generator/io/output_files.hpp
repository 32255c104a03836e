// Atomic output: a failed run leaves earlier files untouched.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "model/inert_text.hpp"

namespace sweepgen::io {

struct OutputFile {
  std::string path;
  std::string text;
};

// Writes every file to a temporary name in its directory, then renames them all into place.
// On any failure the temporaries are removed, nothing already there is changed, and an
// IoError naming the path is thrown. A file that already holds exactly its text is left alone,
// time stamp included, so that a build regenerating unchanged output recompiles nothing.
void write_files_atomically(const std::vector<OutputFile>& files);

// A failure to read or write `path`: the path is shown through inert_text, as in InputError.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  IoError(const std::string& path, const std::string& reason)
      : std::runtime_error(inert_text(path, kShownPathBytes) + ": " + reason) {}
};

// FNV-1a, 64 bit, as 16 hex digits: the provenance hash of inputs (not a security measure).
std::string fnv1a64(const std::string& bytes);

// The whole content of a file; throws IoError naming it.
std::string read_file(const std::string& path);

}  // namespace sweepgen::io
