#include "io/output_files.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace sweepgen::io {
namespace {

// Whether the file at `path` exists and holds exactly `text`.
bool holds(const std::string& path, const std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream existing;
  existing << in.rdbuf();
  return existing.str() == text;
}

}  // namespace

void write_files_atomically(const std::vector<OutputFile>& files) {
  std::vector<std::string> temporaries;
  std::vector<const OutputFile*> changed;
  const auto discard = [&temporaries] {
    for (const auto& t : temporaries) std::remove(t.c_str());
  };
  for (const auto& file : files) {
    if (holds(file.path, file.text)) continue;
    changed.push_back(&file);
    const std::string temporary = file.path + ".tmp" + std::to_string(::getpid());
    temporaries.push_back(temporary);
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << file.text;
    out.flush();
    if (!out) {
      const std::string reason = std::strerror(errno);
      discard();
      throw IoError(file.path, "cannot write (" + reason + ")");
    }
  }
  for (std::size_t i = 0; i < changed.size(); ++i) {
    if (std::rename(temporaries[i].c_str(), changed[i]->path.c_str()) != 0) {
      const std::string reason = std::strerror(errno);
      discard();
      throw IoError(changed[i]->path, "cannot replace (" + reason + ")");
    }
  }
}

std::string fnv1a64(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace sweepgen::io
