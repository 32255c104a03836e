#include "model/quarter_turns.hpp"

#include <tinyxml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "model/error.hpp"

namespace sweepgen::model {
namespace {

constexpr double kHalfPi = 1.5707963267948966;

// The multiple of pi/2 that `angle` is within 1e-10 rad of, if any.
bool near_quarter_turn(double angle, long& quarter_turns) {
  const double turns = std::round(angle / kHalfPi);
  quarter_turns = static_cast<long>(turns);
  return std::abs(angle - turns * kHalfPi) < 1e-10;
}

// Exact sine and cosine of k quarter turns.
void quarter_turn_sin_cos(long k, double& s, double& c) {
  static constexpr double kSin[4] = {0, 1, 0, -1};
  static constexpr double kCos[4] = {1, 0, -1, 0};
  const long index = ((k % 4) + 4) % 4;
  s = kSin[index];
  c = kCos[index];
}

// R = Rz(yaw) Ry(pitch) Rx(roll), each angle within 1e-10 rad of a multiple of pi/2 taken as that
// multiple (`snapped`, `quarter_turns` say which and which).
Mat3 quarter_turn_rule(const std::array<double, 3>& rpy, std::array<bool, 3>& snapped, std::array<long, 3>& quarter_turns) {
  double s[3], c[3];
  for (int k = 0; k < 3; ++k) {
    // 0 is a multiple of pi/2 too, but taking it as 0 changes nothing.
    snapped[k] = near_quarter_turn(rpy[k], quarter_turns[k]) && rpy[k] != 0;
    if (snapped[k]) {
      quarter_turn_sin_cos(quarter_turns[k], s[k], c[k]);
    } else {
      s[k] = std::sin(rpy[k]);
      c[k] = std::cos(rpy[k]);
    }
  }
  Mat3 Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, c[0], -s[0], 0, s[0], c[0];
  Ry << c[1], 0, s[1], 0, 1, 0, -s[1], 0, c[1];
  Rz << c[2], -s[2], 0, s[2], c[2], 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

}  // namespace

OriginRotation origin_rotation(const urdf::Rotation& rotation, bool snap) {
  OriginRotation result;
  rotation.getRPY(result.rpy[0], result.rpy[1], result.rpy[2]);
  const Mat3 literal = Eigen::Quaterniond(rotation.w, rotation.x, rotation.y, rotation.z).normalized().toRotationMatrix();
  if (!snap) {
    result.R = literal;
    return result;
  }
  result.R = quarter_turn_rule(result.rpy, result.snapped, result.quarter_turns);
  // The angle of R^T literal, from its skew part (the sine of the angle: accurate for small ones).
  const Mat3 between = result.R.transpose() * literal;
  const Mat3 skew = between - between.transpose();
  result.deviation = 0.5 * Eigen::Vector3d(skew(2, 1), skew(0, 2), skew(1, 0)).norm();
  return result;
}

std::map<std::string, std::string> written_rpy(const std::string& urdf_text) {
  std::map<std::string, std::string> written;
  TiXmlDocument document;
  document.Parse(urdf_text.c_str());
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (!robot) return written;
  const auto rpy_of = [](const TiXmlElement* parent) -> const char* {
    const TiXmlElement* origin = parent ? parent->FirstChildElement("origin") : nullptr;
    return origin ? origin->Attribute("rpy") : nullptr;
  };
  for (const TiXmlElement* joint = robot->FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint"))
    if (const char* name = joint->Attribute("name"); name && rpy_of(joint))
      written["joint " + quote_name(name) + " <origin>"] = rpy_of(joint);
  for (const TiXmlElement* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link"))
    if (const char* name = link->Attribute("name"); name && rpy_of(link->FirstChildElement("inertial")))
      written["link " + quote_name(name) + " <inertial> <origin>"] = rpy_of(link->FirstChildElement("inertial"));
  return written;
}

std::string quarter_turns_as_written(const std::string& taken_as, const std::string& rpy_attribute) {
  // taken_as lists three angles, each a multiple of pi/2 as text ("0", "pi/2", "-pi", ...) or a number.
  std::istringstream taken(taken_as.size() > 2 ? taken_as.substr(1, taken_as.size() - 2) : "");
  int angles = 0;
  for (std::string angle; std::getline(taken, angle, ','); ++angles)
    if (angle.find("pi") == std::string::npos && angle != "0" && angle != " 0") return "";
  std::istringstream written(rpy_attribute);
  std::string text = "(";
  for (int k = 0; k < 3; ++k) {
    double angle = 0;
    long quarter_turns = 0;
    if (!(written >> angle) || !near_quarter_turn(angle, quarter_turns)) return "";
    text += (k ? ", " : "") + quarter_turns_text(quarter_turns);
  }
  std::string rest;
  return angles == 3 && !(written >> rest) ? text + ")" : "";
}

std::string quarter_turns_text(long k) {
  if (k == 0) return "0";
  const long half_turns = k / 2;
  if (k % 2 == 0) return (half_turns == 1 ? "" : half_turns == -1 ? "-" : std::to_string(half_turns)) + "pi";
  return (k == 1 ? "" : k == -1 ? "-" : std::to_string(k)) + "pi/2";
}

}  // namespace sweepgen::model
