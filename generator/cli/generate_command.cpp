#include "cli/generate_command.hpp"

#include <filesystem>
#include <iostream>

#include "cli/command_line.hpp"
#include "io/output_files.hpp"
#include "emit/scene_request.hpp"
#include "emit/solver_emitter.hpp"
#include "emit/templates.hpp"
#include "model/error.hpp"
#include "model/model_notes.hpp"
#include "scene/canonical_text.hpp"
#include "scene/cpp_names.hpp"
#include "scene/scene.hpp"
#include "solver/shared_body_sets.hpp"

namespace sweepgen::cli {
namespace {

void add_scene_options(CLI::App* command, SceneOptions& options) {
  command->add_option("--scene", options.scene, "scene file (YAML)");
  command->add_option("--urdf", options.urdf, "URDF file (without --scene: the default scene for it)");
  command->add_option("--root", options.root, "root link");
  command->add_option("--tip", options.tip, "tip link");
  command->add_option("--solver", options.solver, "C++ namespace of the generated solver");
  command->add_option("--expose", options.expose, "all | outputs")->check(CLI::IsMember({"all", "outputs"}));
  command->add_option("--scalar", options.scalars, "double and/or float (repeatable)")
      ->check(CLI::IsMember({"double", "float"}));
  command->add_option("--branch-tip", options.branch_tips,
                      "a further tip (repeatable): the moving joints on the paths to every tip form a tree (scene key tips)");
  command->add_flag("--floating-base", options.floating_base,
                    "the root link moves freely (scene key base: floating; docs/derivation.md, F5)");
  command->add_flag("--no-snap-quarter-turns", options.literal_angles,
                    "take URDF angles as written, not within 1e-10 rad of a multiple of pi/2 as exact (scene key "
                    "snap_quarter_turns: false)");
  command->add_option("--mimic", options.mimic,
                      "independent: each <mimic> joint a joint of its own (the default); coupled: held to its source "
                      "exactly, q and qd without it (scene key mimic; docs/derivation.md, M1)")
      ->check(CLI::IsMember({"independent", "coupled"}));
  command->add_flag("--notes", options.all_notes,
                    "every note on the URDF, a line each (as the generated header lists them), not one line per kind "
                    "with its count");
  // Neither a scene nor a URDF is a usage error (exit 2), like any other missing option.
  command->parse_complete_callback([&options] {
    if (options.scene.empty() && options.urdf.empty()) throw CLI::RequiredError("--scene or --urdf");
  });
}

// The scene the options describe: the file (or the default scene for --urdf), with flags
// overriding its entries.
scene::Scene resolve_scene(const SceneOptions& options) {
  if (options.scene.empty() && options.urdf.empty())
    throw InputError("command line", "--scene / --urdf", "give a scene file, or a URDF for the default scene");
  scene::Scene s = options.scene.empty()
                       ? scene::default_scene(options.urdf, options.root, options.tip, options.branch_tips, !options.literal_angles,
                                              options.command)
                       : scene::load_scene(options.scene);
  const auto override_with = [&s](const std::string& value, std::string& field, const char* element, const char* flag) {
    if (value.empty()) return;
    field = value;
    s.locations[element] = flag;
  };
  if (!options.scene.empty()) {
    override_with(options.urdf, s.chain.urdf, "urdf", "--urdf");
    override_with(options.root, s.chain.root_link, "root", "--root");
    override_with(options.tip, s.chain.tip_link, "tip", "--tip");
    if (!options.branch_tips.empty()) {
      s.chain.branch_tips = options.branch_tips;
      s.locations["tip"] = "--branch-tip";
    }
    if (!options.tip.empty() || !options.branch_tips.empty())  // the file's `tips` entries no longer name them
      for (auto it = s.locations.begin(); it != s.locations.end();)
        it = it->first.rfind("tips[", 0) == 0 ? s.locations.erase(it) : std::next(it);
    if (options.literal_angles) s.chain.snap_quarter_turns = false;
  }
  if (!options.solver.empty()) {
    if (const std::string problem = scene::solver_namespace_problem(options.solver); !problem.empty())
      throw InputError("--solver", "solver", problem);
    s.solver = options.solver;
  }
  if (options.floating_base) {
    s.chain.floating_base = true;
    s.locations["base"] = "--floating-base";
  }
  if (!options.mimic.empty()) {
    s.chain.couple_mimics = options.mimic == "coupled";
    s.chain.mimic_location = "--mimic " + options.mimic;
  }
  if (!options.expose.empty()) s.expose_all = options.expose == "all";
  if (!options.scalars.empty()) s.scalars = options.scalars;
  return s;
}

std::string templates_hash() {
  std::string all;
  for (const auto& [name, text] : emit::embedded_templates()) all += name + '\0' + text + '\0';
  return io::fnv1a64(all);
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// The provenance line hashes the model and scene as read (canonical_text), not the files' bytes:
// an edit that changes no number or name (a comment, white space) leaves the output as it was.
emit::EmittedSolver emit_scene(const scene::Scene& s, const model::Chain& chain) {
  const std::string provenance =
      std::string("Generated by sweepgen ") + SWEEPGEN_VERSION + " from " +
      (s.path.empty() ? std::string("the default scene") : "scene " + inert_text(file_name(s.path))) + " and URDF " +
      inert_text(file_name(s.chain.urdf)) + " (fnv1a64 " + io::fnv1a64(scene::canonical_text(s, chain)) +
      " of their numbers and names as read, not of the files' bytes), templates (fnv1a64 " + templates_hash() +
      "). Do not edit: regenerate with `sweepgen generate`.";
  return emit::emit_solver(chain, emit::emit_request(s, provenance));
}

// What the scene and the model do not take as written, or leave to the application (Scene::notes,
// model_notes): every note, or the URDF's as one line per kind of them (model_note_summary).
void print_notes(const scene::Scene& s, const model::Chain& chain, bool all_notes, std::ostream& out) {
  for (const std::string& line : s.notes) out << "sweepgen: note: " << inert_text(line, kShownPathBytes) << "\n";
  for (const std::string& line : all_notes ? model::model_notes(chain) : model::model_note_summary(chain))
    out << "sweepgen: note: " << line << "\n";
}

// What the scene allows but will likely not do what was meant (solver/shared_body_sets.hpp).
void print_warnings(const scene::Scene& s, const model::Chain& chain) {
  std::vector<std::string> warnings = solver::shared_body_warnings(s.layout.constraint_sets(), chain);
  for (const std::string& line : solver::redundant_loop_warnings(s.layout.constraint_sets(), chain)) warnings.push_back(line);
  for (const std::string& line : warnings)
    std::cerr << "sweepgen: warning: " << (s.path.empty() ? std::string("command line") : inert_text(s.path, kShownPathBytes)) << ": " << line << "\n";
}

void print_costs(const emit::EmittedSolver& emitted, std::ostream& out) {
  for (const std::string& choice : emitted.choices) out << "  " << choice << "\n";
  for (const auto& cost : emitted.costs)
    if (cost.scalar == emitted.costs.front().scalar) out << "  " << cost.function << ": " << cost.ops.summary() << "\n";
}

}  // namespace

void add_generate_command(CLI::App& app, GenerateOptions& options) {
  CLI::App* command = app.add_subcommand("generate", "Emit the solver a scene describes");
  options.scene.command = "sweepgen generate";
  add_scene_options(command, options.scene);
  command->add_option("--out", options.out, "output directory (created if missing)")->capture_default_str()->check(kNonEmptyPath);
  command->add_option("--file-stem", options.file_stem,
                      "name of the output files inside --out, STEM.hpp/.cpp/.cu/.cmake: letters, digits, '_', '-', '.' "
                      "(default: from the namespace)");
  command->add_option("--depfile", options.depfile, "write a Makefile depfile listing the scene and URDF");
  command->add_flag("--quiet", options.quiet,
                    "print nothing on success but warnings: not the files written, the notes on the URDF or the "
                    "operation counts (`sweepgen info` prints those)");
}

void add_info_command(CLI::App& app, SceneOptions& options) {
  CLI::App* command = app.add_subcommand("info", "Summarise a chain and the cost of its default (or given) scene");
  options.command = "sweepgen info";
  add_scene_options(command, options);
}

namespace {

// Why `stem` is not a plain file name, or "": the output files are `stem`.hpp, .cpp and .cmake
// inside --out, and the .cpp includes the header by that name, the .cmake lists the .cpp.
std::string file_stem_problem(const std::string& stem) {
  if (stem.empty()) return "is empty";
  if (stem[0] == '.' || stem[0] == '-') return "must not start with '.' or '-'";
  if (stem.size() > 200) return "is longer than 200 characters";
  for (char c : stem)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.'))
      return "may contain only letters, digits, '_', '-' and '.' (a file name inside --out, not a path)";
  return "";
}

// A path as a depfile spells it for both GNU make and Ninja: space, '#' and ':' after a backslash,
// '$' doubled; any other backslash is read as it is by both. An InputError for a path no depfile
// can hold alike for both: a line break or other control character, or a backslash before a
// space, '#', ':' or at the end (make halves such a run of backslashes, Ninja keeps all but one).
std::string depfile_path(const std::string& path, const std::string& element) {
  const auto refuse = [&](const std::string& what) {
    throw InputError(element, quote_name(path), "a path with " + what + " cannot be written to --depfile");
  };
  const std::string escaped = " #:";
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const char c = path[i];
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) refuse("a control character");
    if (c == '\\' && (i + 1 == path.size() || escaped.find(path[i + 1]) != std::string::npos))
      refuse("a backslash before a space, '#', ':' or at its end");
    if (escaped.find(c) != std::string::npos) out += '\\';
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

}  // namespace

int run_generate(const GenerateOptions& options) {
  if (const std::string problem = file_stem_problem(options.file_stem); !options.file_stem.empty() && !problem.empty())
    throw InputError("--file-stem", quote_name(options.file_stem), problem);
  const scene::Scene s = resolve_scene(options.scene);
  const model::Chain chain = scene::load_scene_chain(s);
  print_warnings(s, chain);
  emit::EmittedSolver emitted = emit_scene(s, chain);

  std::error_code error;
  std::filesystem::create_directories(options.out, error);
  if (error) throw io::IoError(options.out, "cannot create directory (" + error.message() + ")");
  const std::string default_stem = emit::file_stem(s.solver);
  std::vector<io::OutputFile> files;
  for (auto& file : emitted.files) {
    std::string name = file.name;
    if (!options.file_stem.empty()) name = options.file_stem + name.substr(default_stem.size());
    if (!options.file_stem.empty()) {
      // The .cpp includes the header, the .cu the .cpp, the .cmake lists the .cpp: by file name.
      const auto rename_reference = [&file](const std::string& from, const std::string& to) {
        const auto at = file.text.find(from);
        if (at != std::string::npos) file.text.replace(at, from.size(), to);
      };
      rename_reference("#include \"" + default_stem + ".hpp\"", "#include \"" + options.file_stem + ".hpp\"");
      rename_reference("/" + default_stem + ".cpp", "/" + options.file_stem + ".cpp");
      rename_reference("#include \"" + default_stem + ".cpp\"", "#include \"" + options.file_stem + ".cpp\"");
    }
    files.push_back({(std::filesystem::path(options.out) / name).string(), file.text});
  }
  if (!options.depfile.empty()) {
    std::string deps = depfile_path(files.front().path, "--out") + ":";
    for (const std::string& input : {s.path, s.chain.urdf})
      if (!input.empty()) deps += " " + depfile_path(std::filesystem::absolute(input).string(), input == s.path ? "--scene" : "urdf");
    files.push_back({options.depfile, deps + "\n"});
  }
  io::write_files_atomically(files);
  if (options.quiet) return 0;
  std::cout << "sweepgen: " << s.solver << " (" << chain.dof() << " joints, Nc = " << s.layout.constraints
            << "): wrote";
  for (const auto& f : files) std::cout << " " << f.path;
  std::cout << "\n";
  print_notes(s, chain, options.scene.all_notes, std::cout);
  print_costs(emitted, std::cout);
  return 0;
}

int run_info(const SceneOptions& options) {
  const scene::Scene s = resolve_scene(options);
  const model::Chain chain = scene::load_scene_chain(s);
  print_warnings(s, chain);
  std::string tips = inert_text(chain.tip_link);
  for (const std::string& tip : chain.branch_tips) tips += ", " + inert_text(tip);
  std::cout << (chain.is_chain() ? "chain " : "tree ") << inert_text(chain.root_link) << " -> " << tips << " in "
            << inert_text(chain.source, kShownPathBytes) << ": " << chain.dof() << " moving joints\n";
  if (s.locations.count("tip") == 0)  // neither the scene nor a flag named it (urdf_loader.cpp, deepest_link)
    std::cout << "  tip " << inert_text(chain.tip_link)
              << ": none named; the last link of the one moving branch (what hangs below it on fixed joints is "
                 "lumped into it); name another with --tip or the scene key tip\n";
  const bool is_chain = chain.is_chain();
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const auto& j = chain.joints[i];
    const auto& b = chain.bodies[i];
    if (j.floating_base_coordinate) {
      std::cout << "  " << i << ". " << j.name << " (floating-base coordinate: " << (i <= 3 ? "angular" : "linear")
                << " velocity of " << inert_text(chain.root_link) << " along its " << "xyz"[(i - 1) % 3] << " axis)\n";
      continue;
    }
    const bool axis_aligned = (j.axis.array().abs() == 1.0).any();
    std::cout << "  " << i << ". " << inert_text(j.name) << " (" << (j.type == model::JointType::revolute ? (j.continuous ? "continuous" : "revolute") : "prismatic")
              << ", axis " << j.axis.transpose() << (axis_aligned ? ", axis-aligned: folds to one column" : "")
              << ") moves " << inert_text(b.link) << (is_chain ? "" : " against " + inert_text(chain.bodies[chain.parent[i]].link))
              << ", mass " << b.mass << " kg";
    std::cout << ", effort limit " << j.effort_limit << ", rotor inertia " << j.rotor_inertia;
    if (const model::JointCoupling* coupling = chain.coupling_of(i))  // (M1)
      std::cout << ", coupled: q = " << coupling->multiplier << " q_" << coupling->source << " + " << coupling->offset
                << " (" << quote_name(chain.joints[coupling->source].name) << "; no input of its own; coupling_torque["
                << coupling - chain.couplings.data() << "])";
    else
      for (const auto& mimic : chain.mimics)
        if (mimic.joint == j.name) std::cout << ", a <mimic> of " << quote_name(mimic.source) << " (see the notes)";
    std::cout << "\n";
  }
  std::cout << "links carried by the chain (lumped: fixed, or behind a locked joint off the chain), locked joints, links left out:\n";
  for (const std::string& line : model::lumping_summary(chain)) std::cout << "  " << line << "\n";
  const auto sets = solver::constraint_set_summary(s.layout);
  if (!sets.empty()) std::cout << "constraint sets (alpha and set_acceleration in each set's link frame):\n";
  for (const std::string& line : sets) std::cout << "  " << line << "\n";
  const emit::EmittedSolver emitted = emit_scene(s, chain);
  std::cout << "scene " << (s.path.empty() ? "(default)" : inert_text(s.path, kShownPathBytes)) << ", solver " << s.solver << ", Nc = " << s.layout.constraints
            << ", operation counts:\n";
  print_costs(emitted, std::cout);
  print_notes(s, chain, options.all_notes, std::cout);
  return 0;
}

}  // namespace sweepgen::cli
