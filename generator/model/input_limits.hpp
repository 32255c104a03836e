// The limits on what sweepgen reads (README, "Limits"): far above real robots (a humanoid has a few
// dozen joints and a few hundred links; a scene a handful of driver instances), low enough that a
// hostile or broken file is refused at once with the limit named, before any work grows with it,
// instead of filling the memory, overflowing the stack or running for hours.
#pragma once

#include <cstddef>
#include <string>

namespace sweepgen {

constexpr std::size_t kMaxUrdfBytes = std::size_t{32} << 20;      // a URDF file
constexpr std::size_t kMaxSceneBytes = std::size_t{8} << 20;      // a scene file
constexpr std::size_t kMaxSolveLineBytes = std::size_t{8} << 20;  // one line of `sweepgen solve` input
// A file of results for `sweepgen report --judge`: about 100 000 states of the largest bundled
// scene (2.6 KiB a line in hex floats); the GPU benchmark writes 1 000.
constexpr std::size_t kMaxJudgedBytes = std::size_t{256} << 20;
// Elements inside elements in a URDF (a URDF needs 4: robot, link, inertial, mass). TinyXML, the
// reader under urdfdom, recurses once per level.
constexpr std::size_t kMaxXmlDepth = 100;
// Collections inside collections in a scene: the YAML reader's own guard (yaml-cpp's DepthGuard).
constexpr std::size_t kMaxYamlDepth = 2000;
// Entries of one sequence or mapping in a scene: ten times what any key takes (driver instances,
// locked joints and tips are bounded by kMaxInstances, kMaxJoints and kMaxLinks), so that a key's
// own limit speaks first.
constexpr std::size_t kMaxYamlItems = 100000;
// Values (scalars and collections) in a scene: the YAML reader spends some 600 bytes on each,
// counted before it builds them (scene/yaml_outline.hpp).
constexpr std::size_t kMaxYamlNodes = 200000;
// Elements in a URDF: TinyXML spends some 250 bytes on each, counted before it reads them
// (xml_nesting.hpp); a link or joint takes a few to a few dozen.
constexpr std::size_t kMaxXmlElements = 1000000;
constexpr std::size_t kMaxLinks = 10000;   // <link> elements of a URDF
constexpr std::size_t kMaxJoints = 10000;  // <joint> elements of a URDF
constexpr std::size_t kMaxInstances = 10000;  // driver instances of a scene (torques and external forces)
// Steps of the constraint rows (I6) where a scene asks for them (constraint_rows: outward_rows):
// they grow with the square of a chain's length, N (N + 1) / 2 for a set at its tip, about a
// 1 400-joint chain (solver/constraint_row_steps.hpp).
constexpr std::size_t kMaxOutwardRowSteps = 1000000;

// The magnitude of a robot's physical numbers (a mass, a diagonal moment of inertia, a gravity
// component): 0, or within [kSmallestModelNumber, kLargestModelNumber]. Real robots lie within
// 1e-20..1e20 in SI units (arm_micro's inertias ~1e-11 kg m^2, arm_giant's 1e7); the sweeps
// multiply and divide up to about five such numbers (m l^2, its inverse, squared in E^A_cstr),
// which stays within double's 1e+-308 from numbers within 1e+-60, where 1e308 overflows to Inf
// and a subnormal 4.9e-324 makes 1/D overflow and 0 * Inf a NaN.
constexpr double kSmallestModelNumber = 1e-60;
constexpr double kLargestModelNumber = 1e60;

// "" for a number within those bounds, else the reason naming them.
std::string magnitude_problem(double value);

// "32 MiB" for a size in bytes.
std::string size_text(std::size_t bytes);

// The file's bytes, at most `limit` of them: a longer file (or an endless one, /dev/zero) is
// refused, naming `what` and the limit, after reading limit + 1 bytes. Throws InputError.
std::string read_input_file(const std::string& path, std::size_t limit, const std::string& what);

}  // namespace sweepgen
