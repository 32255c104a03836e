// Atomic output: a failed run leaves earlier files untouched; no write lands outside the named files.
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

// Writes every file to a new temporary in its directory (created exclusively under a name
// nobody can predict, never through a link or over an existing file; mode 0666 less the umask;
// flushed to the disk), then renames them all into place. On any failure the temporaries are
// removed, nothing already there is changed, and an IoError naming the path is thrown. A file
// that already holds exactly its text is left alone, time stamp included, so that a build
// regenerating unchanged output recompiles nothing; only a regular file of the text's size is
// read for that comparison: a link, a FIFO or a device at the name is replaced, not read.
// Each file is replaced atomically, the set is not: a reader may see some files of this call
// beside others of a concurrent one (the generated solver's files check each other for that).
void write_files_atomically(const std::vector<OutputFile>& files);

// Whether `path` is a regular file holding exactly `text`. A link (to /dev/zero, say), a FIFO, a
// device or a file of another size is not read at all (false), so that no comparison can hang,
// read without end or read through a link.
bool holds(const std::string& path, const std::string& text);

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
