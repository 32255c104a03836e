// Hostile and huge inputs (README, "Limits"): names that hold a line break, a comment's end, a
// backslash, a trigraph, bidirectional controls, NUL or bytes that are not UTF-8 reach the generated
// code inert (it compiles under -Werror) and messages escaped; every limit is enforced before the
// work with a message naming it; nesting and graph depth do not reach the call stack; --file-stem
// stays inside --out; messages stay short. The large inputs are made here, on the fly.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/inert_text.hpp"
#include "model/input_limits.hpp"
#include "model/xml_nesting.hpp"
#include "solver/drivers.hpp"
#include "support/run_command.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;
using test::CommandResult;

// Everything a name can carry that could act in generated code: a line break followed by a
// preprocessor line, a comment's end and start, a trigraph that would end in a line splice, a
// right-to-left override (U+202E), bytes that are not UTF-8 and, last, a backslash (before a
// line break it continues a // comment into the next line).
const std::string kHostile = "\n#error injected\n */ /* ?\?/ \xE2\x80\xAE \xff\xfe \\";
// The same but valid UTF-8: what a YAML scene can spell ("\xff" in YAML is U+00FF, not a byte).
const std::string kHostileUtf8 = "\n#error injected\n */ /* ?\?/ \xE2\x80\xAE \\";

CommandResult sweepgen(const std::vector<std::string>& args, const std::string* input = nullptr) {
  std::vector<std::string> words{SWEEPGEN_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  return test::run_command(test::shell_command(words), input);
}

std::string describe(const CommandResult& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out.substr(0, 4000) + "\n--- stderr:\n" +
         r.err.substr(0, 4000);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Whether `text` is valid UTF-8 (RFC 3629) without control characters other than '\n'.
bool printable_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto b = static_cast<unsigned char>(text[i]);
    if (b < 0x80) {
      if ((b < 0x20 && b != '\n') || b == 0x7f) return false;
      ++i;
      continue;
    }
    const std::size_t n = b >= 0xf0 && b <= 0xf4 ? 4 : b >= 0xe0 ? 3 : b >= 0xc2 && b <= 0xdf ? 2 : 0;
    if (n == 0 || i + n > text.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return false;
    i += n;
  }
  return true;
}

// Writes `text` to `dir`/`folder`/`name`, creating the folder: a path may hold "*/" and "??\" across
// its separator, which a file name cannot.
std::string write_file(const fs::path& dir, const std::string& folder, const std::string& name, const std::string& text) {
  fs::create_directories(dir / folder);
  std::ofstream(dir / folder / name, std::ios::binary) << text;
  return (dir / folder / name).string();
}

// A name as an XML attribute value: line breaks as character references, the rest raw.
std::string xml(const std::string& name) {
  std::string out;
  for (char c : name) out += c == '\n' ? std::string("&#10;") : std::string(1, c);
  return out;
}

// A robot whose every name ends in `payload`: a fixed base carrying a link fixed to it (left out),
// two moving joints (the second a <mimic> of the first, with <dynamics>, an axis of length 2), a tip
// fixed behind a quarter turn, and a moving side branch off the first body (locked, lumped).
std::string hostile_urdf(const std::string& payload) {
  const auto n = [&](const std::string& stem) { return xml(stem + payload); };
  const std::string inertial =
      "<inertial><origin xyz=\"0.1 0 0\"/><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" "
      "iyz=\"0\" izz=\"0.01\"/></inertial>";
  const auto link = [&](const std::string& stem) { return "  <link name=\"" + n(stem) + "\">" + inertial + "</link>\n"; };
  const auto joint = [&](const std::string& stem, const std::string& type, const std::string& parent,
                         const std::string& child, const std::string& extra) {
    return "  <joint name=\"" + n(stem) + "\" type=\"" + type + "\"><parent link=\"" + n(parent) + "\"/><child link=\"" +
           n(child) + "\"/>" + extra + "</joint>\n";
  };
  const std::string limit = "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/>";
  return "<robot name=\"" + n("robot") + "\">\n" + link("base") + link("plate") + link("upper") + link("lower") +
         link("hand") + link("side") + joint("bolt", "fixed", "base", "plate", "") +
         joint("shoulder", "revolute", "base", "upper", "<axis xyz=\"0 0 2\"/>" + limit) +
         joint("elbow", "revolute", "upper", "lower",
               "<origin xyz=\"0 0 0.3\"/><axis xyz=\"0 1 0\"/>" + limit + "<mimic joint=\"" + n("shoulder") +
                   "\"/><dynamics damping=\"0.5\"/>") +
         joint("wrist", "fixed", "lower", "hand", "<origin xyz=\"0 0 0.2\" rpy=\"1.5707963267 0 0\"/>") +
         joint("side", "revolute", "upper", "side", "<axis xyz=\"1 0 0\"/>" + limit) + "</robot>\n";
}

// generate, then the .cpp (which includes the header) compiled by the system compiler with every
// warning an error: a line break in a comment would leave `#error injected` a directive, `*/`
// would end no comment but `/*` inside one is -Wcomment, "??/" is -Wtrigraphs, U+202E is
// -Wbidi-chars, a trailing backslash would splice the next line into the comment. Under
// -std=gnu++17, CMake's default, where the compiler defines macros such as `linux` too.
void expect_generated_code_compiles(const std::vector<std::string>& generate_args, const fs::path& out) {
  std::vector<std::string> args{"generate"};
  args.insert(args.end(), generate_args.begin(), generate_args.end());
  args.insert(args.end(), {"--out", out.string()});
  const CommandResult generated = sweepgen(args);
  ASSERT_EQ(generated.exit_code, 0) << describe(generated);
  EXPECT_TRUE(printable_utf8(generated.out)) << generated.out;
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string text = test::read_text(entry.path());
    EXPECT_TRUE(printable_utf8(text)) << entry.path();
    EXPECT_FALSE(contains(text, "\n#error")) << entry.path();
    ++files;
    if (entry.path().extension() != ".cpp") continue;
    const CommandResult compiled = test::run_command(test::shell_command(
        {"c++", "-std=gnu++17", "-fsyntax-only", "-Wall", "-Wextra", "-Wpedantic", "-Werror", entry.path().string()}));
    EXPECT_EQ(compiled.exit_code, 0) << describe(compiled);
  }
  EXPECT_EQ(files, 4u);  // .hpp, .cpp, .cu (which includes the .cpp) and .cmake
}

// ---- The inert text function ------------------------------------------------------------------

TEST(InertText, EscapesWhatCouldActAndKeepsPlainNames) {
  EXPECT_EQ(inert_text("panda_link0"), "panda_link0");
  EXPECT_EQ(inert_text("world (where base is now)"), "world (where base is now)");
  EXPECT_EQ(quote_name("a'b"), "'a\\'b'");
  EXPECT_EQ(inert_text("a\nb"), "'a\\nb'");
  EXPECT_EQ(inert_text(std::string("a\0b", 3)), "'a\\0b'");
  EXPECT_EQ(inert_text("x */ y /* z"), "'x *\\/ y /\\* z'");
  EXPECT_EQ(inert_text("/*/"), "'/\\*\\/'");
  EXPECT_EQ(inert_text("a?\?/"), "'a?\\?/'");
  EXPECT_EQ(inert_text("tail\\"), "'tail\\\\'");  // never ends in a backslash: the quote closes it
  EXPECT_EQ(inert_text("\xff\xfe"), "'\\xff\\xfe'");
  EXPECT_EQ(inert_text("\xc3"), "'\\xc3'");                        // a lead byte without its continuation
  EXPECT_EQ(inert_text("\xed\xa0\x80"), "'\\xed\\xa0\\x80'");      // a surrogate: not UTF-8
  EXPECT_EQ(inert_text("\xc0\xaf"), "'\\xc0\\xaf'");               // an overlong '/'
  EXPECT_EQ(inert_text("r\xE2\x80\xAEl"), "'r\\u{202e}l'");         // right-to-left override
  EXPECT_EQ(inert_text("Gelenk_\xC3\xA4"), "'Gelenk_\xC3\xA4'");    // valid UTF-8 stays, quoted
  for (const std::string& name : {kHostile, kHostileUtf8}) {
    const std::string inert = inert_text(name);
    EXPECT_TRUE(printable_utf8(inert)) << inert;
    EXPECT_FALSE(contains(inert, "\n") || contains(inert, "*/") || contains(inert, "/*") || contains(inert, "??"));
    EXPECT_NE(inert.back(), '\\');
  }
}

TEST(InertText, CutsALongNameWithItsSize) {
  const std::string token(1 << 20, 'x');
  const std::string quoted = quote_name(token);
  EXPECT_EQ(quoted, "'" + std::string(kShownBytes, 'x') + "'... (1048576 bytes)");
  // Cut at a character's end, not inside a UTF-8 sequence.
  std::string wide;
  while (wide.size() < 3 * kShownBytes) wide += "\xC3\xA4";
  EXPECT_TRUE(printable_utf8(quote_name(wide)));
  EXPECT_EQ(listed({"a", "b", "c"}, 2), "a, b and 1 more");
}

TEST(XmlOutline, CountsElementsAsTheParserNestsThem) {
  const model::XmlOutline outline = model::xml_outline(
      "<?xml version=\"1.0\"?>\n<!-- <a><b><c> -->\n<robot a=\"/>\" b='>'>\n  <link name=\"x\"/>\n"
      "  <link><inertial><![CDATA[<d><e>]]></inertial></link>\n  <joint/>\n  <x><link/></x>\n</robot>\n");
  EXPECT_EQ(outline.depth, 3u);
  EXPECT_EQ(outline.deepest_line, 5u);
  EXPECT_EQ(outline.links, 2u);   // the <link> inside <x> is not the robot's
  EXPECT_EQ(outline.joints, 1u);
  // A quote inside an unquoted value opens no quoted text (the parser reads on: nothing hidden);
  // names may start with any byte from 127 up, as TinyXML's do.
  EXPECT_EQ(model::xml_outline("<r a=b\"><s><t><u></u></t></s></r>").depth, 4u);
  EXPECT_EQ(model::xml_outline("<r><\x7f><\xc3\xa4/></\x7f></r>").depth, 3u);
}

// ---- The table, row by row ------------------------------------------------------------

// Row 1: a joint name holding a line break went raw into // comments (`#error injected`). Every
// name a URDF carries (links, joints, the fixed, lumped, locked, left-out, mimic, changed ones) and
// the URDF's file name, in the default scene.
TEST(HostileInputs, NamesFromTheUrdfReachTheGeneratedCodeInert) {
  const test::TempDir dir;
  const std::string urdf = write_file(dir.path(), "robot *", " ??\\\xff\xE2\x80\xAE.urdf", hostile_urdf(kHostile));
  expect_generated_code_compiles({"--urdf", urdf, "--tip", "hand" + kHostile}, dir.path() / "out");
  const CommandResult info = sweepgen({"info", "--urdf", urdf, "--tip", "hand" + kHostile});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  EXPECT_TRUE(printable_utf8(info.out)) << info.out;
  EXPECT_FALSE(contains(info.out, "\n#error"));
}

// ... and every name a scene carries (tips, external-force and constraint-set links, locked joints,
// rotor inertias), the scene's and the URDF's file names in the provenance line.
TEST(HostileInputs, NamesFromASceneReachTheGeneratedCodeInert) {
  const test::TempDir dir;
  write_file(dir.path(), "robot *", " ??\\.urdf", hostile_urdf(kHostileUtf8));
  const std::string y = "\\n#error injected\\n */ /* ?\?/ \\u202E \\\\";  // kHostileUtf8 in YAML's escapes
  const std::string scene = write_file(dir.path(), "scene *", "\n??\\scene.yaml",
                                      "sweepgen_scene: 1\nsolver: hostile\nurdf: \"../robot */ ??\\\\.urdf\"\n"
                                      "tips: [\"hand" + y + "\"]\n"
                                      "locked_joints: {\"side" + y + "\": 0.5}\n"
                                      "rotor_inertia: {\"shoulder" + y + "\": 0.01}\n"
                                      "drivers:\n  torques: [tau]\n  external_forces:\n"
                                      "    - {name: push, link: \"lower" + y + "\"}\n"
                                      "  constraints:\n    - {link: \"hand" + y + "\", count: 2}\n"
                                      "policies: [original, saturate]\nscalars: [double, float]\n");
  expect_generated_code_compiles({"--scene", scene}, dir.path() / "out");
}

// Names that could clash with the generated code's own, in one scene, compiled: driver names
// that are its locals, arguments, types and functions, a torque `alpha_0` beside the run-time
// directions (whose locals are alpha_<k>_<i>, the torque's drivers_alpha_0_<i>), and a
// namespace whose parts are the generated code's names. The names that cannot compile are
// refused (tests/test_scene.cpp, SceneErrors.*CannotCompile).
TEST(HostileInputs, NamesTheGeneratedCodeUsesItselfCompile) {
  const test::TempDir dir;
  dir.write("robot.urdf", hostile_urdf(""));
  const std::string scene = dir.write(
      "scene.yaml",
      "sweepgen_scene: 1\nsolver: f64::Lanes::Batch::state::std_\nurdf: robot.urdf\ntip: hand\n"
      "drivers:\n  torques: [alpha_0, alpha_1, alpha_0_1, i, k, n, q, qd, beta, in, out, cursor, residue, drivers_in,\n"
      "            drivers, state, nq, std, Drivers, State, Solution, Lanes, Batch, FlatDrivers, f64, sin_q_1,\n"
      "            status_ok, flat_in_size, outward, decompose, solve_original, derivatives_original]\n"
      "  external_forces: [{name: alpha_1_0, link: hand}, {name: tau_ff, link: lower}]\n"
      "  constraints: 2\n"
      "policies: [original, prioritize_external, saturate, saturate_exact]\nscalars: [double, float]\nderivatives: true\n");
  expect_generated_code_compiles({"--scene", scene}, dir.path() / "out");
}

// NUL, which XML cannot carry (&#0; is no character) but YAML can ("\0"): in messages as \0.
TEST(HostileInputs, NulInASceneNameIsReportedEscaped) {
  const test::TempDir dir;
  dir.write("robot.urdf", hostile_urdf(""));
  const std::string scene = dir.write("scene.yaml",
                                      "sweepgen_scene: 1\nsolver: s\nurdf: robot.urdf\ntip: hand\n"
                                      "rotor_inertia: {\"shoulder\\0\\n\": 0.01}\n");
  const CommandResult r = sweepgen({"info", "--scene", scene});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_TRUE(contains(r.err, "'shoulder\\0\\n'")) << r.err;
  EXPECT_TRUE(printable_utf8(r.err)) << r.err;
}

// Row 2: a byte 0xFF in a solve line aborted (nlohmann's type_error.316 while printing the error
// line); so did a "did you mean" hint naming a link that is not UTF-8, and a saturated joint's name.
TEST(HostileInputs, InvalidUtf8InASolveLineIsReportedNotThrown) {
  const test::TempDir dir;
  const std::string urdf = dir.write("robot.urdf", hostile_urdf("\xff"));
  const std::string lines =
      "{\"q\": [0, 0], \"qd\": [0, 0], \"f_ext\": {\"lower\xff\": [0, 0, 0, 0, 0, 0]}}\n"  // not UTF-8: not JSON
      "{\"q\": [0, 0], \"qd\": [0, 0], \"f_ext\": {\"lowr\": [0, 0, 0, 0, 0, 0]}}\n"       // the hint names 'lower\xff'
      "{\"q\": [0, 0], \"qd\": [0, 0], \"tau_ff\": [1000, 1000], \"policy\": \"saturate_exact\"}\n";
  const CommandResult r = sweepgen({"solve", "--urdf", urdf, "--tip", "hand\xff"}, &lines);
  ASSERT_EQ(r.exit_code, 1) << describe(r);  // not 134 (abort)
  std::vector<nlohmann::json> out;  // each line valid JSON (and so valid UTF-8)
  for (std::size_t at = 0, end; (end = r.out.find('\n', at)) != std::string::npos; at = end + 1)
    out.push_back(nlohmann::json::parse(r.out.substr(at, end - at)));
  ASSERT_EQ(out.size(), 3u) << r.out;
  EXPECT_TRUE(contains(out[0]["error"].get<std::string>(), "\\xff")) << out[0];
  EXPECT_TRUE(contains(out[1]["error"].get<std::string>(), "did you mean 'lower\\xff'")) << out[1];
  EXPECT_TRUE(contains(out[2].value("status", ""), "saturated")) << out[2];  // answered, not an error line
  EXPECT_EQ(out[2].value("saturated_joints", nlohmann::json::array()).size(), 2u) << out[2];
  EXPECT_TRUE(printable_utf8(r.err)) << r.err;
}

// Row 3: a URDF nested 100 000 deep overflowed the stack inside TinyXML.
TEST(HostileInputs, DeeplyNestedUrdfIsRefusedBeforeParsing) {
  const test::TempDir dir;
  std::string text = "<robot name=\"r\">\n";
  for (int k = 0; k < 100000; ++k) text += "<a>";
  for (int k = 0; k < 100000; ++k) text += "</a>";
  const std::string urdf = dir.write("deep.urdf", text + "\n</robot>\n");
  const CommandResult r = sweepgen({"info", "--urdf", urdf});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_TRUE(contains(r.err, "deep.urdf:2: <robot>: elements nested 100001 deep, more than the limit of 100")) << r.err;
}

// Row 4: 10 000 external-force instances took more than 600 s and overflowed the sanitizer build's
// stack in the recursive schedule; a sum over the instances was also written as one expression
// nested as deep. Here as many as the limit allows, on one body (each a term of that body's force
// sum: the graph as deep as there are instances), generated with a stack of 512 KiB, which either
// recursion overflowed (exit 139).
TEST(HostileInputs, ManyInstancesNeedNoDeepStack) {
  const test::TempDir dir;
  dir.write("robot.urdf", hostile_urdf(""));
  std::string scene = "sweepgen_scene: 1\nsolver: many\nurdf: robot.urdf\ntip: hand\ndecomposition: composed\n"
                      "drivers:\n  external_forces:\n";
  for (std::size_t k = 0; k < kMaxInstances; ++k) scene += "    - {name: f" + std::to_string(k) + ", link: lower}\n";
  const std::string path = dir.write("many.yaml", scene);
  const CommandResult r = test::run_command(
      "ulimit -s 512 && " + test::shell_command({SWEEPGEN_EXECUTABLE, "generate", "--scene", path, "--out",
                                                  (dir.path() / "out").string()}));
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  // And the source grows with the instances, not with their square: 1 196 bytes per instance
  // measured (each instance's member, its unpacking, its not-finite check, its view and its term of
  // the force sum); flat_drivers_of once spelled each offset as a sum of every earlier instance's
  // six (`drivers_in + 6 + 6 + ...`), one line of 200 MB here (21 186 bytes per instance). 2 KiB
  // per instance leaves room for a longer name per instance or a line more, and is a tenth of that.
  const auto bytes = std::filesystem::file_size(dir.path() / "out" / "many.cpp");
  EXPECT_LT(bytes, 2048 * kMaxInstances) << bytes << " bytes for " << kMaxInstances << " instances";
}

// ... and past the limit, refused before anything is traced.
TEST(HostileInputs, InstancesPastTheLimitAreRefused) {
  const test::TempDir dir;
  std::string scene = "sweepgen_scene: 1\nsolver: many\nurdf: robot.urdf\ndrivers:\n  torques: [";
  for (std::size_t k = 0; k <= kMaxInstances; ++k) scene += (k ? ", t" : "t") + std::to_string(k);
  const CommandResult r = sweepgen({"info", "--scene", dir.write("many.yaml", scene + "]\n")});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_TRUE(contains(r.err, "drivers.torques: more than 10000 driver instances")) << r.err;
}

// Row 5: a long chain's generate went as n^3 (model::joint_inertia_bounds) and beyond; the bench
// (bench/input_scaling.sh) measures the time, this the limits and that the walks over a chain's
// links (the loader's search for the tip, urdfdom's links freeing one another) do not reach the
// stack: with 512 KiB either overflowed (exit 139).
TEST(HostileInputs, LongChainsNeedNoDeepStack) {
  const test::TempDir dir;
  // A chain of 9 999 fixed joints (the most links the limit allows), then one moving joint; the
  // root link listed last, so that urdfdom's map frees the links tip first.
  std::string text = "<robot name=\"r\">\n";
  const std::string inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";
  for (int k = 9999; k >= 1; --k) text += "<link name=\"l" + std::to_string(k) + "\">" + inertial + "</link>\n";
  text += "<link name=\"z0\"/>\n";
  for (int k = 1; k <= 9999; ++k)
    text += "<joint name=\"j" + std::to_string(k) + "\" type=\"" + (k == 1 ? "revolute" : "fixed") +
            "\"><parent link=\"" + (k == 1 ? std::string("z0") : "l" + std::to_string(k - 1)) + "\"/><child link=\"l" +
            std::to_string(k) + "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
  const std::string urdf = dir.write("long.urdf", text + "</robot>\n");
  const std::string line = "{\"q\": [0.1], \"qd\": [0]}\n";
  const CommandResult r = test::run_command(
      "ulimit -s 512 && " + test::shell_command({SWEEPGEN_EXECUTABLE, "solve", "--urdf", urdf}), &line);
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  // One link over the limit, refused from the file's outline.
  const std::string more = dir.write("more.urdf", text + "<link name=\"extra\"/>\n</robot>\n");
  const CommandResult refused = sweepgen({"info", "--urdf", more});
  EXPECT_EQ(refused.exit_code, 1) << describe(refused);
  EXPECT_TRUE(contains(refused.err, "10001 <link> elements, more than the limit of 10000")) << refused.err;
}

// Row 6: --file-stem with a path wrote outside --out.
TEST(HostileInputs, FileStemIsAPlainFileName) {
  const test::TempDir dir;
  const std::string urdf = dir.write("robot.urdf", hostile_urdf(""));
  const fs::path out = dir.path() / "a" / "b" / "out";
  for (const std::string stem : {"sub/../../escaped", "../escaped", "/tmp/escaped", "..", ".hidden", "a b"}) {
    const CommandResult r = sweepgen({"generate", "--urdf", urdf, "--tip", "hand", "--out", out.string(), "--file-stem", stem});
    EXPECT_EQ(r.exit_code, 1) << stem << ": " << describe(r);
    EXPECT_TRUE(contains(r.err, "--file-stem: ")) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "a")) << "written outside --out, or --out itself, on a refused stem";
  EXPECT_FALSE(fs::exists("/tmp/escaped.hpp"));
  const CommandResult r = sweepgen({"generate", "--urdf", urdf, "--tip", "hand", "--out", out.string(), "--file-stem", "my-solver.v2"});
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_TRUE(fs::exists(out / "my-solver.v2.hpp"));
  EXPECT_TRUE(contains(test::read_text(out / "my-solver.v2.cpp"), "#include \"my-solver.v2.hpp\""));
}

// Row 7: an endless input (/dev/zero) was read until the memory ran out.
TEST(HostileInputs, EndlessInputsStopAtTheLimit) {
  const CommandResult urdf = sweepgen({"info", "--urdf", "/dev/zero"});
  EXPECT_EQ(urdf.exit_code, 1) << describe(urdf);
  EXPECT_TRUE(contains(urdf.err, "/dev/zero: file: larger than 32 MiB, the limit for a URDF")) << urdf.err;
  const CommandResult scene = sweepgen({"info", "--scene", "/dev/zero"});
  EXPECT_EQ(scene.exit_code, 1) << describe(scene);
  EXPECT_TRUE(contains(scene.err, "larger than 8 MiB, the limit for a scene")) << scene.err;
  const test::TempDir dir;
  const std::string urdf_file = dir.write("robot.urdf", hostile_urdf(""));
  const CommandResult solve = sweepgen({"solve", "--urdf", urdf_file, "--tip", "hand", "--input", "/dev/zero"});
  EXPECT_EQ(solve.exit_code, 1) << describe(solve);
  EXPECT_TRUE(contains(solve.err, "/dev/zero:1: line longer than 8 MiB, the limit")) << solve.err;
  const CommandResult judged = sweepgen({"report", "--scene", std::string(SWEEPGEN_SOURCE_DIR) + "/robots/planar/planar_nc2.yaml",
                                         "--judge", "/dev/zero"});
  EXPECT_EQ(judged.exit_code, 1) << describe(judged);
  EXPECT_TRUE(contains(judged.err, "/dev/zero: file: larger than 256 MiB, the limit for a file of results (--judge)"))
      << judged.err;
}

// ---- The other limits, and messages kept short ------------------------------------------------

TEST(HostileInputs, OtherLimitsAreNamed) {
  const test::TempDir dir;
  std::string joints = "<robot name=\"r\">\n<link name=\"a\"/>\n";
  for (std::size_t k = 0; k <= kMaxJoints; ++k) joints += "<joint name=\"j" + std::to_string(k) + "\" type=\"fixed\"/>\n";
  const CommandResult j = sweepgen({"info", "--urdf", dir.write("joints.urdf", joints + "</robot>\n")});
  EXPECT_EQ(j.exit_code, 1) << describe(j);
  EXPECT_TRUE(contains(j.err, "10001 <joint> elements, more than the limit of 10000")) << j.err;

  const std::string deep_yaml =
      "sweepgen_scene: 1\nsolver: s\nurdf: robot.urdf\ngravity: " + std::string(3000, '[') + std::string(3000, ']') + "\n";
  const CommandResult y = sweepgen({"info", "--scene", dir.write("deep.yaml", deep_yaml)});
  EXPECT_EQ(y.exit_code, 1) << describe(y);
  EXPECT_TRUE(contains(y.err, "YAML: collections nested more than 2000 deep, the limit")) << y.err;

  dir.write("robot.urdf", hostile_urdf(""));
  std::string sets = "{\"q\": [0, 0], \"qd\": [0, 0], \"constraints\": [";
  for (std::size_t k = 0; k <= solver::kMaxConstraints; ++k)
    sets += std::string(k ? ", " : "") + "{\"link\": \"hand\", \"alpha\": [[0, 0, 0, 0, 0, 1]], \"beta\": [0]}";
  const std::string line = sets + "]}\n";
  const CommandResult c = sweepgen({"solve", "--urdf", (dir.path() / "robot.urdf").string(), "--tip", "hand"}, &line);
  EXPECT_EQ(c.exit_code, 1) << describe(c);
  EXPECT_TRUE(contains(c.err, "key 'constraints': at most 24 directions in all, got 25 sets")) << c.err;
}

// Inputs within the size limits cost some 300 times their size in the readers' trees: an 8 MiB
// scene `gravity: [0,0,0,...]` took 31 s and 2.5 GB before "expected 3 numbers", a 32 MiB URDF of
// `<a/>` elements 19 s and 1.9 GB before it was accepted. Both are now refused by their outline,
// before the trees (the messages are the outline checks'; bench/input_scaling.sh measures time
// and memory).
TEST(HostileInputs, LongSequencesAndManyElementsAreRefusedByTheirOutline) {
  const test::TempDir dir;
  std::string zeros = "sweepgen_scene: 1\nsolver: s\nurdf: robot.urdf\ngravity: [0";
  while (zeros.size() < kMaxSceneBytes - 16) zeros += ",0";
  const CommandResult gravity = sweepgen({"info", "--scene", dir.write("gravity.yaml", zeros + "]\n")});
  EXPECT_EQ(gravity.exit_code, 1) << describe(gravity);
  EXPECT_TRUE(contains(gravity.err, "gravity.yaml:4:10: gravity: a sequence of more than 100000 entries, more than any "
                                    "scene key takes (the limit")) << gravity.err;

  // Short sequences, many of them: the count of all values.
  std::string lists = "sweepgen_scene: 1\nsolver: s\nurdf: robot.urdf\ngravity: [";
  std::string hundred = "[0";  // a sequence and 99 numbers
  for (int k = 1; k < 99; ++k) hundred += ",0";
  for (std::size_t k = 0; k <= kMaxYamlNodes / 100; ++k) lists += hundred + "],";
  const CommandResult values = sweepgen({"info", "--scene", dir.write("values.yaml", lists + "]\n")});
  EXPECT_EQ(values.exit_code, 1) << describe(values);
  EXPECT_TRUE(contains(values.err, ": gravity[")) << values.err;
  EXPECT_TRUE(contains(values.err, "]: more than 200000 values in the scene, the limit")) << values.err;

  std::string elements = "<robot name=\"r\">\n";
  while (elements.size() < kMaxUrdfBytes - 16) elements += "<a/>";
  const CommandResult a = sweepgen({"info", "--urdf", dir.write("elements.urdf", elements + "\n</robot>\n")});
  EXPECT_EQ(a.exit_code, 1) << describe(a);
  EXPECT_TRUE(contains(a.err, "elements.urdf:2: <a>: more than 1000000 XML elements, the limit")) << a.err;
}

// A list of 10 000 children and a 1 MB token were echoed whole (an 89 KB line; the token twice).
TEST(HostileInputs, MessagesStayShort) {
  const test::TempDir dir;
  std::string wide = "<robot name=\"r\">\n<link name=\"root\"/>\n";
  for (int k = 0; k < 9998; ++k)
    wide += "<link name=\"c" + std::to_string(k) + "\"/><joint name=\"f" + std::to_string(k) +
            "\" type=\"continuous\"><parent link=\"root\"/><child link=\"c" + std::to_string(k) + "\"/></joint>\n";
  const CommandResult children = sweepgen({"info", "--urdf", dir.write("wide.urdf", wide + "</robot>\n")});
  EXPECT_EQ(children.exit_code, 1) << describe(children);
  EXPECT_TRUE(contains(children.err, "'c0', 'c1', ")) << children.err;
  EXPECT_TRUE(contains(children.err, " and 9988 more")) << children.err;
  EXPECT_LT(children.err.size(), 1000u) << children.err;

  const std::string token(1 << 20, 'x');
  dir.write("robot.urdf", hostile_urdf(""));
  const std::string scene =
      dir.write("token.yaml", "sweepgen_scene: 1\nsolver: s\nurdf: robot.urdf\ngravity: [" + token + ", 0, 0]\n");
  const CommandResult yaml = sweepgen({"info", "--scene", scene});
  EXPECT_EQ(yaml.exit_code, 1) << describe(yaml);
  EXPECT_TRUE(contains(yaml.err, "'... (1048576 bytes)")) << yaml.err.substr(0, 1000);
  EXPECT_LT(yaml.err.size(), 1000u);

  const std::string line = "{\"q\": [" + token + "]}\n";
  const CommandResult json = sweepgen({"solve", "--urdf", (dir.path() / "robot.urdf").string(), "--tip", "hand"}, &line);
  EXPECT_EQ(json.exit_code, 1) << describe(json);
  EXPECT_LT(json.err.size(), 1000u) << json.err.substr(0, 1000);
  EXPECT_LT(json.out.size(), 1000u);
}

// Issue 49: inputs the bundled planar arm used to abort on (std::logic_error from the literal of
// a NaN constant). `generate` and `info` both answer with exit 1 and the reason; nothing is written.
const std::string kPlanarUrdf = std::string(SWEEPGEN_SOURCE_DIR) + "/robots/planar/planar_rpr.urdf";

std::string planar_scene(const std::string& urdf, const std::string& gravity, const std::string& constraints) {
  return "sweepgen_scene: 1\nsolver: planar\nurdf: " + urdf + "\ntip: tool\ngravity: " + gravity +
         "\ndrivers:\n  torques: [tau_ff]\n  constraints: " + constraints + "\npolicies: [original]\nscalars: [double]\n";
}

// `generate` and `info` on the scene: exit 1, each part of `message` on standard error, no abort,
// nothing under --out.
void expect_refused(const test::TempDir& dir, const std::string& scene_text, const std::vector<std::string>& message) {
  const std::string scene = dir.write("scene.yaml", scene_text);
  const fs::path out = dir.path() / "out";
  for (const std::string command : {"generate", "info"}) {
    std::vector<std::string> args{command, "--scene", scene};
    if (command == std::string("generate")) args.insert(args.end(), {"--out", out.string()});
    const CommandResult r = sweepgen(args);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    for (const std::string& part : message) EXPECT_TRUE(contains(r.err, part)) << part << "\n" << describe(r);
    EXPECT_FALSE(contains(r.err, "terminate")) << describe(r);
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(HostileInputs, AFixedDirectionNoJointMovesIsRefusedAtItsEntry) {
  const test::TempDir dir;
  expect_refused(dir,
                 planar_scene(kPlanarUrdf, "[0, -9.81, 0]",
                              "[{link: link2, count: 1}, {link: tool, directions: [[0,0,0,0,0,1]]}]"),
                 {"scene.yaml:8:", "drivers.constraints[1].directions[0]: no joint moves link 'tool' along [0, 0, 0, 0, 0, 1]"});
}

TEST(HostileInputs, GravityFarOutsideARobotsRangeIsRefused) {
  const test::TempDir dir;
  expect_refused(dir, planar_scene(kPlanarUrdf, "[0, 0, 1e308]", "{directions: [[0,0,0,1,0,0]]}"),
                 {"scene.yaml:5:", "gravity[2]: gravity component 1e+308 is outside the range of a robot's numbers"});
}

// The URDF's masses and inertia diagonals likewise, each at its link.
TEST(HostileInputs, MassesAndInertiasFarOutsideARobotsRangeAreRefused) {
  const test::TempDir dir;
  std::ifstream in(kPlanarUrdf);
  const std::string urdf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = urdf;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::string heavy = dir.write("heavy.urdf", replaced("<mass value=\"2\"/>", "<mass value=\"1e308\"/>"));
  expect_refused(dir, planar_scene(heavy, "[0, -9.81, 0]", "{directions: [[0,0,0,1,0,0]]}"),
                 {"link 'link1' <inertial>: mass 1e+308 is outside the range of a robot's numbers"});
  const std::string tiny = dir.write(
      "tiny.urdf", replaced("ixx=\"0.0008333333333333335\" ixy=\"0\" ixz=\"0\" iyy=\"0.042083333333333334\" iyz=\"0\" "
                            "izz=\"0.042083333333333334\"",
                            "ixx=\"4.9e-324\" ixy=\"0\" ixz=\"0\" iyy=\"4.9e-324\" iyz=\"0\" izz=\"4.9e-324\""));
  expect_refused(dir, planar_scene(tiny, "[0, -9.81, 0]", "{directions: [[0,0,0,1,0,0]]}"),
                 {"link 'link1' <inertial>: ixx 4.9406564584124654e-324 is outside the range of a robot's numbers"});
  // Inertia 1e308 on the last body was "has no inertia about this joint's axis" (its trace overflowed).
  const std::string huge = dir.write(
      "huge.urdf", replaced("ixx=\"0.00013333333333333334\" ixy=\"0\" ixz=\"0\" iyy=\"0.0038166666666666666\" iyz=\"0\" "
                            "izz=\"0.0038166666666666666\"",
                            "ixx=\"1e308\" ixy=\"0\" ixz=\"0\" iyy=\"1e308\" iyz=\"0\" izz=\"1e308\""));
  expect_refused(dir, planar_scene(huge, "[0, -9.81, 0]", "{directions: [[0,0,0,1,0,0]]}"),
                 {"link 'link3' <inertial>: ixx 1e+308 is outside the range of a robot's numbers"});
}

// Numbers within the bounds whose constants still leave the scalar's range (gravity 1e60 is a
// float's Inf): the emitter names the quantity and the numbers, instead of writing "inff".
TEST(HostileInputs, AConstantThatIsNotANumberInTheScalarNamesTheQuantity) {
  const test::TempDir dir;
  std::string scene = planar_scene(kPlanarUrdf, "[0, 0, 1e60]", "{directions: [[0,0,0,1,0,0]]}");
  scene.replace(scene.find("scalars: [double]"), 17, "scalars: [float]");
  expect_refused(dir, scene,
                 {"planar_rpr.urdf: generated ", "is computed from a constant that is NaN or too large for float",
                  "gravity [0, 0, 1e+60]", "masses from "});
}

// Item 7 of issue 49: a DOCTYPE is refused where it stands; a path with a line break is shown
// escaped, on one line; `--out ''` is a usage error.
TEST(HostileInputs, ADoctypeIsRefusedWithItsPlace) {
  const test::TempDir dir;
  const std::string urdf = dir.write("dtd.urdf", "<?xml version=\"1.0\"?>\n  <!DOCTYPE robot>\n<robot name=\"r\"/>\n");
  const CommandResult r = sweepgen({"info", "--urdf", urdf});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_TRUE(contains(r.err, "dtd.urdf:2:3: XML: a document type declaration (<!DOCTYPE ...>): a URDF has no DTD"))
      << describe(r);
}

TEST(HostileInputs, APathWithALineBreakIsShownOnOneLine) {
  const test::TempDir dir;
  const std::string scene = dir.write("bad\nname.yaml", "sweepgen_scene: 1\nsolver: [\n");
  const fs::path out = dir.path() / "out";
  const CommandResult r = sweepgen({"generate", "--scene", scene, "--out", out.string()});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_TRUE(contains(r.err, "bad\\nname.yaml")) << describe(r);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
  EXPECT_FALSE(fs::exists(out));
  const CommandResult missing = sweepgen({"generate", "--scene", (dir.path() / "no\nfile.yaml").string(), "--out", out.string()});
  EXPECT_EQ(missing.exit_code, 1) << describe(missing);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << describe(missing);
}

TEST(HostileInputs, AnEmptyOutIsAUsageError) {
  const CommandResult r =
      sweepgen({"generate", "--scene", std::string(SWEEPGEN_SOURCE_DIR) + "/robots/planar/planar_nc2.yaml", "--out", ""});
  EXPECT_EQ(r.exit_code, 2) << describe(r);
  EXPECT_TRUE(contains(r.err, "--out: an empty path")) << describe(r);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
