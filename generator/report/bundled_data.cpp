#include "report/bundled_data.hpp"

#include "model/error.hpp"

namespace sweepgen::report {

std::filesystem::path bundled_data_dir() {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  // SWEEPGEN_DATA_FROM_PROGRAM: the installed data directory relative to the installed program's.
  const fs::path installed = (program.parent_path() / SWEEPGEN_DATA_FROM_PROGRAM).lexically_normal();
  const fs::path source = SWEEPGEN_SOURCE_DIR;
  for (const fs::path& dir : {installed, source})
    if (fs::is_directory(dir / "robots", error)) return dir;
  throw InputError((installed / "robots").string(), "bundled scenes",
                   "not installed there, and the source tree this program was built from (" + source.string() +
                       ") has no robots/ either; give --scene FILE or --urdf FILE, or reinstall the package");
}

}  // namespace sweepgen::report
