#include "emit/function_writer.hpp"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>
#include <sstream>

#include "emit/equations.hpp"
#include "emit/lane_groups.hpp"
#include "emit/literal.hpp"
#include "emit/names.hpp"
#include "model/inert_text.hpp"

namespace sweepgen::emit {
namespace {

using symbolic::Field;
using symbolic::Node;
using symbolic::Op;

constexpr int kAtom = 100, kUnary = 3, kProduct = 2, kSum = 1, kTernary = 0;

// Every generated function is a template over its value type S: the scalar, or a Batch of states
// in vector lanes (templates/lanes.mustache). Literals keep the scalar's spelling.
constexpr const char* kValueType = "S";

// The computed values of a function above which it is written in parts (find_parts), and the most
// in one part. Each cut hands values on through memory: quadruped_stance's outward() (9 363 values)
// in parts of 4 000 ran 2.8 % more instructions per solve, in parts of 8 000 1.8 % more, and its
// file compiles fast whole; a 36-joint humanoid's outward() and decompose() (9 705, 9 914) in parts
// of 4 000 run 2.7 % fewer and compile in half the time (bench/README.md, "Compile time of big
// robots"). Parts of 8 000 did not shorten the humanoid's batch object.
constexpr std::size_t kSplitAbove = 9500, kPartNodes = 4000;

class Writer {
 public:
  Writer(const symbolic::Trace& trace, const Plan& plan, const FunctionPlan& function, const model::Chain& chain,
         const std::string& scalar)
      : trace_(trace), graph_(trace.graph), plan_(plan), f_(function), chain_(chain), scalar_(scalar) {}

  FunctionText write() {
    name_fields();
    count_uses();
    find_hoisted();
    find_split();
    name_leaves();
    collect_stores();
    lanes_ = find_lane_groups(trace_, f_);
    find_angles();
    const std::vector<std::size_t> cuts = find_parts();
    if (!cuts.empty() && !angles_.empty()) write_angles();  // before the parts: each reads them
    std::size_t part_begin = 0;
    for (std::size_t cut : cuts) {
      write_part(part_begin, cut);
      part_begin = cut;
    }
    write_nodes(part_begin, f_.computed.size());
    store_rest();
    OpCount worst = ops_;
    worst += worst_extra_;
    ops_ += taken_extra_;
    return {text_.str(), ops_, worst, vector_expressions_};
  }

 private:
  // computed[begin, end), each path block as its if/else.
  void write_nodes(std::size_t begin, std::size_t end_of_range) {
    for (std::size_t i = begin; i < end_of_range;) {
      std::size_t end = i + 1;
      if (f_.path_block[i] == 0) {
        write_node(f_.computed[i], ops_);
      } else {
        while (end < f_.computed.size() && f_.path_block[end] == f_.path_block[i]) ++end;
        write_path_block(i, end);
      }
      i = end;
    }
  }

  // A function of more than kSplitAbove computed values is written in parts: each but the last a
  // lambda that is not inlined (SWEEPGEN_PART), which the compiler optimises alone, called in
  // order; the last part is the function's own code. The compiler's time on one function grows
  // faster than its size (bench/README.md, "Compile time of big robots"). The parts end where
  // the fewest values computed before are read after, near equal sizes, before the first path
  // block of (C4) (whose `return false` belongs to the function). Returns the first index of
  // each part after the first (empty: one part).
  std::vector<std::size_t> find_parts() {
    const std::size_t n = f_.computed.size();
    if (n <= kSplitAbove) return {};
    // Where each value is written: its own place if it is declared, its group's first member's
    // for a lane, its one user's if it is written inside that user's expression.
    std::map<NodeId, std::size_t> index_of, user_of;
    for (std::size_t i = 0; i < n; ++i) index_of[f_.computed[i]] = i;
    for (std::size_t i = 0; i < n; ++i) {
      const Node& node = graph_.node(f_.computed[i]);
      for (int k = 0; k < symbolic::arity(node.op); ++k) user_of[node.args[k]] = i;
    }
    written_at_.assign(n, 0);
    std::vector<std::size_t> group_first(lanes_.groups.size(), n);
    for (std::size_t i = 0; i < n; ++i)
      if (const auto lane = lanes_.lane_of.find(f_.computed[i]); lane != lanes_.lane_of.end())
        group_first[lane->second.first] = std::min(group_first[lane->second.first], i);
    for (std::size_t i = n; i-- > 0;) {
      const NodeId id = f_.computed[i];
      if (const auto lane = lanes_.lane_of.find(id); lane != lanes_.lane_of.end())
        written_at_[i] = group_first[lane->second.first];
      else if (angle_of_.count(id) || local_.count(id) || uses_[id] != 1 || hoisted_.count(id) || split_.count(id) ||
               f_.path_block[i] != 0 || !user_of.count(id))
        written_at_[i] = i;
      else
        written_at_[i] = written_at_[user_of.at(id)];
    }
    // The last place each value (computed here or a leaf) is read.
    for (std::size_t i = 0; i < n; ++i) {
      const Node& node = graph_.node(f_.computed[i]);
      for (int k = 0; k < symbolic::arity(node.op); ++k) {
        std::size_t& last = last_read_[node.args[k]];
        last = std::max(last, written_at_[i]);
      }
    }
    // Values stored at the end (store_rest: not computed here) are read there.
    for (std::size_t i : f_.fields)
      if (!index_of.count(trace_.fields[i].node)) last_read_[trace_.fields[i].node] = n;
    for (NodeId id : f_.carried_out)
      if (!index_of.count(id)) last_read_[id] = n;
    // Values live across each place: written before it, read at or after it.
    std::vector<long> live(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto last = last_read_.find(f_.computed[i]);
      if (last == last_read_.end() || written_at_[i] != i || last->second <= i) continue;
      ++live[i + 1];
      --live[last->second + 1];
    }
    for (std::size_t i = 1; i <= n; ++i) live[i] += live[i - 1];
    // The cuts that hand on the fewest values in all, each part at most kPartNodes long and at
    // least a quarter of that, none inside a path block (dynamic programming over the places:
    // fewest[c], the least values handed on with a cut at c).
    const std::size_t most = kPartNodes, least = kPartNodes / 4, none = ~std::size_t(0);
    const std::size_t last_cut = n - 1;
    std::vector<std::size_t> fewest(last_cut + 1, none), previous(last_cut + 1, 0);
    fewest[0] = 0;
    for (std::size_t c = least; c <= last_cut; ++c) {
      if (f_.path_block[c - 1] != 0 && f_.path_block[c - 1] == f_.path_block[c]) continue;
      for (std::size_t p = c > most ? c - most : 0; p + least <= c; ++p)
        if (fewest[p] != none && (fewest[c] == none || fewest[p] + live[c] < fewest[c])) {
          fewest[c] = fewest[p] + live[c];
          previous[c] = p;
        }
    }
    std::size_t end = none;  // the last cut
    for (std::size_t p = 1; p <= last_cut; ++p)
      if (fewest[p] != none && n - p <= most && n - p >= least && (end == none || fewest[p] < fewest[end])) end = p;
    std::vector<std::size_t> cuts;
    for (std::size_t c = end; c != none && c != 0; c = previous[c]) cuts.insert(cuts.begin(), c);
    return cuts;
  }

  // computed[begin, end) as a lambda that is not inlined (find_parts), called where it stands.
  // It copies the function's values it reads and takes its reference parameters (and the angles'
  // arrays) by reference; it returns, in a struct, the values that later code reads, which the
  // function and the later parts read from that struct by reference (one store and one load per
  // value handed on, as a State member would cost).
  void write_part(std::size_t begin, std::size_t end) {
    const std::set<NodeId> loaded_before = loaded_;
    std::ostringstream outer;
    outer.swap(text_);
    indent_ = "    ";
    declaring_.clear();
    const std::string part = "part_" + std::to_string(next_part_++), type = "Part" + part.substr(part.find('_'));
    // A part with a path block hands back where a Batch's lanes part: `ok` false.
    const bool blocks = std::any_of(f_.path_block.begin() + begin, f_.path_block.begin() + end, [](int b) { return b != 0; });
    if (blocks) lanes_part_ = "return " + type + "{}";  // ok: false
    recording_ = true;
    write_nodes(begin, end);
    recording_ = false;
    lanes_part_ = "return false";
    indent_ = "  ";
    outer.swap(text_);
    const std::string body = outer.str();
    // The variables declared in the part that later code reads (a lane group's vector, when one
    // of its lanes is read).
    std::vector<HandedOn> outputs;
    std::set<std::string> seen;
    for (const auto& [name, value_type, nodes] : declaring_) {
      bool read_later = false;
      for (NodeId id : nodes)
        if (const auto last = last_read_.find(id); last != last_read_.end() && last->second >= end) read_later = true;
      if (read_later && seen.insert(name).second) outputs.push_back({part, value_type, name});
    }
    // What the part reads of the earlier parts' values, by reference.
    std::string aliases, earlier;
    std::set<std::string> parts_read;
    for (const HandedOn& value : handed_on_)
      if (reads_name(body, value.name)) {
        aliases += "    const " + value.type + "& " + value.name + " = " + value.part + "." + value.name + ";\n";
        if (parts_read.insert(value.part).second) earlier += ", &" + value.part;
      }
    text_ << "\n  // ---- " << f_.name << ", " << part << ": a function of its own (SWEEPGEN_PART) ----\n";
    const bool returns = blocks || !outputs.empty();
    if (returns) {
      text_ << "  struct " << type << " {" << (blocks ? " bool ok;" : "");
      for (const HandedOn& value : outputs) text_ << " " << value.type << " " << value.name << ";";
      text_ << " };\n";
    }
    text_ << "  " << (returns ? "const " + type + " " + part + " = " : "") << "[" << captures(body, true) << earlier
          << "]() SWEEPGEN_PART {\n"
          << aliases << body;
    if (returns) {
      text_ << "    return " << type << "{" << (blocks ? "true" : "");
      for (std::size_t k = 0; k < outputs.size(); ++k) text_ << (k || blocks ? ", " : "") << outputs[k].name;
      text_ << "};\n";
    }
    text_ << "  }();\n";
    if (blocks) text_ << "  if (!" << part << ".ok) return false;  // (C4): the lanes part\n";
    for (const HandedOn& value : outputs) {
      text_ << "  [[maybe_unused]] const " << value.type << "& " << value.name << " = " << part << "." << value.name << ";\n";
      handed_on_.push_back(value);
    }
    loaded_ = loaded_before;  // a later part loads again what it reads
    block_body_ = -2;         // and starts with its banner
    block_array_.clear();
  }

  // Whether `text` names the variable `name` (not as a part of a longer name or a member).
  static bool reads_name(const std::string& text, const std::string& name) {
    const auto identifier = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
      const char before = at == 0 ? ' ' : text[at - 1], after = at + name.size() < text.size() ? text[at + name.size()] : ' ';
      if (!identifier(before) && before != '.' && !identifier(after)) return true;
    }
    return false;
  }

  // The capture list of a lambda with `body`: values by copy, the function's reference
  // parameters (and, for a part, the angles' arrays) by reference where the body uses them.
  static std::string captures(const std::string& body, bool arrays) {
    const auto uses = [&body](const std::string& name, char after) {
      for (std::size_t at = body.find(name + after); at != std::string::npos; at = body.find(name + after, at + 1)) {
        const char before = at == 0 ? ' ' : body[at - 1];
        if (!std::isalnum(static_cast<unsigned char>(before)) && before != '_' && before != '.') return true;
      }
      return false;
    };
    std::string list = "=";
    for (const char* reference : {"state", "drivers", "out"})
      if (uses(reference, '.')) list += std::string(", &") + reference;
    if (arrays)
      for (const char* array : {"sin_angle", "cos_angle"})
        if (uses(array, '[')) list += std::string(", &") + array;
    return list;
  }

  // The field that names node `id` here: one of this function's own, else a State field.
  void name_fields() {
    for (const Field& field : trace_.fields) {
      const bool own = field.group == f_.group;
      if (!own && !is_state_field(field)) continue;
      auto found = field_of_.find(field.node);
      if (found == field_of_.end() || (own && !is_state_field(*found->second) && found->second->group != f_.group))
        field_of_[field.node] = &field;
    }
  }

  void count_uses() {
    for (NodeId id : f_.computed) {
      const Node& n = graph_.node(id);
      for (int k = 0; k < symbolic::arity(n.op); ++k) ++uses_[n.args[k]];
    }
    for (std::size_t i : f_.fields) uses_[trace_.fields[i].node] += 2;  // stored: always a local
    for (NodeId id : f_.carried_out) uses_[id] += 2;
    for (NodeId id : f_.computed) {
      const auto field = field_of_.find(id);
      if (field != field_of_.end())
        local_[id] = field_name(*field->second, !is_state_field(*field->second) && field->second->group != f_.group);
      else if (const std::string name = function_of_input_name(trace_, id); !name.empty())
        local_[id] = name;
    }
  }

  // Inputs and values of earlier functions: named here, loaded right before their first use
  // (short live ranges: a value loaded at the top would occupy a register or a spill slot
  // until then).
  void name_leaves() {
    for (NodeId id : f_.leaves) {
      const Node& n = graph_.node(id);
      std::string source;
      if (n.op == Op::input && plan_.stage[id] == f_.stage) {
        source = input_spelling(trace_, trace_.inputs[n.input]);
        local_[id] = input_local_name(trace_, trace_.inputs[n.input]);
      } else if (plan_.exposed_field.count(id)) {
        const Field& field = trace_.fields[plan_.exposed_field.at(id)];
        source = state_field_access(field);
        local_[id] = field_name(field, false);
      } else {
        source = "state." + plan_.carried_name.at(id);
        local_[id] = plan_.carried_name.at(id);
      }
      leaf_source_[id] = source;
    }
  }

  // A leaf's local, loading it first if this is its first use.
  const std::string& leaf(NodeId id) {
    if (loaded_.insert(id).second) pending_loads_.push_back(id);
    return local_.at(id);
  }

  void flush_loads() {
    for (NodeId id : pending_loads_)
      text_ << indent_ << "const " << kValueType << " " << local_.at(id) << " = " << leaf_source_.at(id) << ";\n";
    pending_loads_.clear();
  }

  // Where each stored node goes: stored right after it is computed, so that it need not stay
  // live (in a register or a spill slot) until the end of the function.
  void collect_stores() {
    for (std::size_t i : f_.fields) {
      const Field& field = trace_.fields[i];
      stores_[field.node].push_back({field_access(field), &field});
    }
    for (NodeId id : f_.carried_out) stores_[id].push_back({"state." + plan_.carried_name.at(id), nullptr});
  }

  // A banner where a block begins: the sweep, body (link and joint) and quantity of the field
  // whose computation the block is (Plan::anchor), with its equation tags.
  void banner_for(NodeId id) {
    if (plan_.anchor[id] == kNoAnchor) return;
    const Field& field = trace_.fields[plan_.anchor[id]];
    const Equation& eq = equation_of(field.array);
    if (field.body != block_body_ || eq.sweep != block_sweep_) {
      block_body_ = field.body;
      block_sweep_ = eq.sweep;
      block_array_.clear();
      text_ << "\n" << indent_ << "// ==== " << eq.sweep << " sweep";
      if (field.body > 0) {
        const auto& joint = chain_.joints[field.body];
        text_ << ", body " << field.body << ": link " << inert_text(chain_.bodies[field.body].link) << ", joint "
              << inert_text(joint.name) << " (" << (joint.type == model::JointType::revolute ? "revolute" : "prismatic")
              << ")";
        if (!chain_.is_chain())
          text_ << ", on body " << chain_.parent[field.body] << " ("
                << inert_text(chain_.bodies[chain_.parent[field.body]].link) << ")";
      } else if (field.body == 0) {
        text_ << ", base: link " << inert_text(chain_.bodies[0].link);
      }
      text_ << " ====\n";
    }
    if (field.array != block_array_) {
      block_array_ = field.array;
      text_ << indent_ << "// " << field.array << ": " << eq.cited() << "\n";
    }
  }

  // A node used once is written inside its user's expression, and so on down: a sum over 10 000
  // driver instances would be one expression nested 10 000 deep, as deep in this writer's calls
  // (operand, expression) and beyond what compilers parse (clang: 256 brackets). A node whose
  // inline operands nest more than kInlineDepth deep is declared as a local instead.
  void find_split() {
    constexpr int kInlineDepth = 64;
    std::map<NodeId, int> depth;  // of the expression that writing the node inline would nest
    for (NodeId id : f_.computed) {
      const Node& n = graph_.node(id);
      int d = 0;
      for (int k = 0; k < symbolic::arity(n.op); ++k) {
        const NodeId a = n.args[k];
        const auto found = depth.find(a);
        if (found != depth.end() && !local_.count(a) && uses_[a] == 1 && !hoisted_.count(a) && !split_.count(a))
          d = std::max(d, found->second);
      }
      depth[id] = d + 1;
      if (d + 1 > kInlineDepth) split_.insert(id);
    }
  }

  // Nodes computed inside a path block that a node of another block reads (a factorisation on one
  // path that two solves on that path use: the refinement, R1, in one function): declared before
  // their block and assigned in it, so that they outlive it.
  void find_hoisted() {
    std::map<NodeId, int> block_of;
    for (std::size_t i = 0; i < f_.computed.size(); ++i) block_of[f_.computed[i]] = f_.path_block[i];
    for (std::size_t i = 0; i < f_.computed.size(); ++i) {
      const Node& n = graph_.node(f_.computed[i]);
      for (int k = 0; k < symbolic::arity(n.op); ++k) {
        const auto found = block_of.find(n.args[k]);
        if (found != block_of.end() && found->second != 0 && found->second != f_.path_block[i] &&
            plan_.guard[n.args[k]] != kAlways)
          hoisted_.insert(n.args[k]);
      }
    }
  }

  void write_node(NodeId id, OpCount& ops) {
    ops.count(graph_.node(id).op);
    if (const auto lane = lanes_.lane_of.find(id); lane != lanes_.lane_of.end()) {
      vector_locals(lane->second.first);  // at the group's first member: every lane's operands are ready
      return;
    }
    if (const auto angle = angle_of_.find(id); angle != angle_of_.end()) {
      write_angle(id, angle->second);
      return;
    }
    if (local_.count(id) || uses_[id] != 1 || hoisted_.count(id) || split_.count(id)) declare(id);
  }

  // The locals holding group g's lanes (lane_groups.hpp), one per chunk (an empty string for a
  // chunk without members), declared on first use: a seed gathers the directions' components
  // from their loads, any other group is one vector expression per chunk of its first member's
  // shape, the operands shared by every lane broadcast.
  const std::vector<std::string>& vector_locals(std::size_t g) {
    if (const auto found = group_locals_.find(g); found != group_locals_.end()) return found->second;
    const LaneGroup& group = lanes_.groups[g];
    const NodeId first = *std::find_if(group.members.begin(), group.members.end(), [](NodeId m) { return m != kNoLane; });
    if (!group.seed) {
      ++vector_expressions_;
      banner_for(first);
    }
    std::vector<std::string> names;
    const std::vector<LaneGroups::Chunk> chunks = LaneGroups::chunks(group.members.size());
    for (std::size_t c = 0; c < chunks.size(); ++c) {
      const LaneGroups::Chunk& chunk = chunks[c];
      const auto begin = group.members.begin() + chunk.first, end = begin + chunk.count;
      const auto present = std::find_if(begin, end, [](NodeId m) { return m != kNoLane; });
      if (present == end) {
        names.emplace_back();
        continue;
      }
      std::string value;
      if (group.seed) {
        for (std::size_t l = 0; l < LaneGroups::kWidth; ++l)
          value += (l ? ", " : "{") + leaf(*(l < chunk.count ? begin + l : begin));
        value += "}";
      } else {
        const Node& n = graph_.node(first);
        const auto lane_operand = [&](int k) {
          return group.lane_operand[k] ? vector_locals(lanes_.lane_of.at(n.args[k]).first).at(c)
                                       : operand(n.args[k], kAtom);
        };
        const std::string a = lane_operand(0);
        value = n.op == Op::neg ? "-" + a : a + vector_operator(n.op) + lane_operand(1);
      }
      flush_loads();
      const std::string name = "lanes" + std::to_string(next_vector_++);
      // Not const: in a batch a group is LaneArray<Batch>, an aggregate, and GCC's scalar replacement
      // of aggregates passes over a const one that is assigned ("store to a read-only decl"): each
      // then stays in memory, a stack slot of its own (bench/README.md, "Lane groups in batches").
      text_ << indent_ << "Lanes" << LaneGroups::kWidth << " " << name << " = " << value << ";\n";
      if (recording_) declaring_.push_back({name, "Lanes" + std::to_string(LaneGroups::kWidth), std::vector<NodeId>(begin, end)});
      for (auto m = begin; m != end; ++m) {
        if (*m == kNoLane) continue;
        local_[*m] = name + "[" + std::to_string(m - begin) + "]";
        declared_[*m] = true;
        if (!group.seed) store(*m);
      }
      names.push_back(name);
    }
    return group_locals_[g] = names;
  }

  // The sin and cos nodes of values known when the function starts (the joint angles, loaded or
  // handed on): one sincos_each call computes them all where the first is needed, several in the
  // lanes of a vector (templates/lanes.mustache), not one C library call each.
  void find_angles() {
    for (std::size_t i = 0; i < f_.computed.size(); ++i) {
      const NodeId id = f_.computed[i];
      const Node& n = graph_.node(id);
      if ((n.op != Op::sin && n.op != Op::cos) || f_.path_block[i] != 0 || lanes_.lane_of.count(id)) continue;
      const NodeId x = n.args[0];
      if (graph_.node(x).op != Op::input && plan_.stage[x] == f_.stage) continue;  // computed here: not known at the start
      const auto [index, added] = angle_index_.emplace(x, angles_.size());
      if (added) angles_.push_back(x);
      angle_of_[id] = index->second;
    }
  }

  void write_angles() {
    angles_written_ = true;
    std::string values;
    for (NodeId x : angles_) values += (values.empty() ? "" : ", ") + leaf(x);
    flush_loads();
    const std::string n = std::to_string(angles_.size());
    text_ << indent_ << "// sin and cos of the joint angles, all at once (F2; sincos_each)\n"
          << indent_ << "const " << kValueType << " angle[" << n << "] = {" << values << "};\n"
          << indent_ << kValueType << " sin_angle[" << n << "], cos_angle[" << n << "];\n"
          << indent_ << "sincos_each(angle, sin_angle, cos_angle);\n";
  }

  void write_angle(NodeId id, std::size_t k) {
    banner_for(id);
    if (!angles_written_) write_angles();
    const std::string element =
        std::string(graph_.node(id).op == Op::sin ? "sin_angle[" : "cos_angle[") + std::to_string(k) + "]";
    if (local_.count(id)) {
      text_ << indent_ << "const " << kValueType << " " << local_[id] << " = " << element << ";\n";
      if (recording_) declaring_.push_back({local_[id], kValueType, {id}});
    } else {
      local_[id] = element;
    }
    declared_[id] = true;
    store(id);
  }

  static const char* vector_operator(Op op) {
    switch (op) {
      case Op::add: return " + ";
      case Op::sub: return " - ";
      case Op::mul: return " * ";
      default: return " / ";
    }
  }

  // computed[begin, end): one if/else on a path condition (Plan::guard). The select_path results
  // are declared before it and assigned in each branch; each branch computes what only it needs.
  // Locals and loads made inside a branch end with it.
  void write_path_block(std::size_t begin, std::size_t end) {
    std::vector<NodeId> branch[2], results;
    for (std::size_t i = begin; i < end; ++i) {
      const NodeId id = f_.computed[i];
      const int g = plan_.guard[id];
      (g == kAlways ? results : branch[g % 2]).push_back(id);
    }
    const NodeId probe = f_.computed[begin];
    const PathCondition& condition = plan_.conditions[plan_.guard[probe] == kAlways
                                                          ? plan_.condition_of(graph_.node(probe))
                                                          : plan_.guard[probe] / 2];
    for (NodeId id : results) {
      banner_for(id);
      local_.try_emplace(id, "e" + std::to_string(next_expression_++));
      text_ << indent_ << kValueType << " " << local_[id] << ";\n";
      if (recording_) declaring_.push_back({local_[id], kValueType, {id}});
    }
    for (int arm = 0; arm < 2; ++arm)
      for (NodeId id : branch[arm])
        if (hoisted_.count(id)) {
          local_.try_emplace(id, "e" + std::to_string(next_expression_++));
          text_ << indent_ << kValueType << " " << local_[id] << ";  // assigned on one path, read by a later block of it\n";
          if (recording_) declaring_.push_back({local_[id], kValueType, {id}});
        }
    const std::string test = binary(condition.greater, kSum, " > ", condition.than, kSum);
    flush_loads();
    // In lanes (a Batch of states), a group whose lanes part returns false, and its states are
    // solved one by one (templates/solver.cpp.mustache, solve_in_lanes); a scalar never does.
    const std::string path = "path_" + std::to_string(next_path_++), base = indent_;
    text_ << indent_ << "const auto " << path << " = " << test << ";  // (C4): the path the condition picks\n";
    text_ << indent_ << "if (Lanes<" << kValueType << ">::all(" << path << ")) {\n";
    OpCount cost[2];
    for (int arm = 0; arm < 2; ++arm) {
      if (arm == 1)
        text_ << indent_ << "} else {\n"
              << indent_ << "  if (Lanes<" << kValueType << ">::any(" << path << ")) " << lanes_part_ << ";  // (C4): the lanes part\n";
      const std::set<NodeId> loaded_before = loaded_;
      // The other path (the pivoted factorisation of (C4)) is written as a function of its own
      // (cold_path): the usual path's optimisation does not see it.
      std::ostringstream usual;
      if (arm == 1) usual.swap(text_);
      indent_ = base + (arm == 1 ? "    " : "  ");
      for (NodeId id : branch[arm]) write_node(id, cost[arm]);
      for (NodeId id : results) {
        const NodeId chosen = graph_.node(id).args[2 + arm];
        const std::string value = operand(chosen, kTernary);
        flush_loads();
        text_ << indent_ << local_[id] << " = "
              << (graph_.node(chosen).op == Op::constant ? "Lanes<" + std::string(kValueType) + ">::of(" + value + ")" : value)
              << ";\n";
      }
      if (arm == 1) {
        usual.swap(text_);
        std::vector<NodeId> outputs = results;
        for (NodeId id : branch[1])
          if (hoisted_.count(id)) outputs.push_back(id);
        indent_ = base + "  ";
        cold_path(path, usual.str(), outputs);
      }
      for (NodeId id : branch[arm])
        if (!hoisted_.count(id)) declared_.erase(id);
      loaded_ = loaded_before;
      indent_ = base;
    }
    text_ << indent_ << "}\n";
    ++ops_.compare;  // the test; the assignments are moves
    for (NodeId id : results) {
      declared_[id] = true;
      store(id);
    }
    taken_extra_ += cost[0];
    worst_extra_ += cost[cost[1].total() > cost[0].total() ? 1 : 0];
  }

  // The body of a path block's other arm as a lambda called where the arm was, which the compiler
  // inlines (marked noinline and cold, it kept the lean scenes' values in memory: 5-7 % more
  // instructions a solve, and bought no compile time once long functions went in parts; bench/
  // README.md, "Compile time of big robots"). It copies the values it reads (only when it runs),
  // takes the function's reference parameters it uses by reference, and returns `outputs` (the
  // block's results and the values it hands on to later blocks), which it declares itself.
  void cold_path(const std::string& path, const std::string& body, const std::vector<NodeId>& outputs) {
    const std::string type = "Pivoted" + path.substr(path.find('_'));
    if (!outputs.empty()) {
      text_ << indent_ << "struct " << type << " {";
      for (NodeId id : outputs) text_ << " " << kValueType << " " << local_.at(id) << ";";
      text_ << " };\n";
    }
    text_ << indent_ << (outputs.empty() ? "" : "const " + type + " pivoted = ") << "[" << captures(body, false)
          << "]() {\n";
    if (!outputs.empty()) {
      text_ << indent_ << " ";
      for (NodeId id : outputs) text_ << " " << kValueType << " " << local_.at(id) << ";";
      text_ << "\n";
    }
    text_ << body;
    if (!outputs.empty()) {
      text_ << indent_ << "  return " << type << "{";
      for (std::size_t k = 0; k < outputs.size(); ++k) text_ << (k ? ", " : "") << local_.at(outputs[k]);
      text_ << "};\n";
    }
    text_ << indent_ << "}();\n";
    for (NodeId id : outputs) text_ << indent_ << local_.at(id) << " = pivoted." << local_.at(id) << ";\n";
  }

  void store(NodeId id) {
    const auto targets = stores_.find(id);
    if (targets == stores_.end()) return;
    for (const auto& [target, field] : targets->second)
      text_ << indent_ << store_statement(target, field, local_[id]) << "\n";
    stores_.erase(targets);
  }

  void declare(NodeId id) {
    banner_for(id);
    if (!local_.count(id)) local_[id] = "e" + std::to_string(next_expression_++);
    const std::string value = expression(id, kTernary);
    flush_loads();
    text_ << indent_ << (hoisted_.count(id) ? "" : std::string("const ") + kValueType + " ") << local_[id] << " = " << value << ";\n";
    if (recording_) declaring_.push_back({local_[id], kValueType, {id}});
    declared_[id] = true;
    store(id);
  }

  // Text of node `id` as an operand of an operator of precedence `context`. Right operands
  // pass their operator's precedence + 1, so the printed code evaluates in the traced order
  // (a + (b + c) stays parenthesised: floating-point addition does not associate).
  std::string operand(NodeId id, int context) {
    const Node& n = graph_.node(id);
    if (n.op == Op::constant) {
      const std::string text = literal(n.value, scalar_);
      return n.value < 0 && context >= kUnary ? "(" + text + ")" : text;
    }
    if (declared_.count(id)) return local_.at(id);
    if (n.op == Op::input || plan_.stage[id] < f_.stage) return leaf(id);
    // Only a node used once is written where it is used; any other is declared before its users
    // (write_node). Reaching one undeclared is a planning error: say so rather than write it out
    // as a tree, which grows exponentially with the graph's sharing.
    if (local_.count(id) || uses_[id] != 1)
      throw std::logic_error("emit: " + f_.name + " reads node " + std::to_string(id) + " before it is computed");
    const int own = precedence(n.op);
    const std::string text = expression(id, own);
    return own < context ? "(" + text + ")" : text;
  }

  static int precedence(Op op) {
    switch (op) {
      case Op::add:
      case Op::sub: return kSum;
      case Op::mul:
      case Op::div: return kProduct;
      case Op::neg: return kUnary;
      case Op::select_greater:
      case Op::select_path: return kTernary;
      default: return kAtom;
    }
  }

  bool is_negative_constant(NodeId id) const {
    return graph_.node(id).op == Op::constant && graph_.node(id).value < 0;
  }

  // c * x with a constant c < 0, written inline: x - c*x reads better as x + |c|*x (exact).
  bool is_negative_scaled(NodeId id) const {
    const Node& n = graph_.node(id);
    return n.op == Op::mul && !declared_.count(id) && !local_.count(id) && uses_.count(id) && uses_.at(id) == 1 &&
           plan_.stage[id] == f_.stage && (is_negative_constant(n.args[0]) || is_negative_constant(n.args[1]));
  }
  std::string negated_scaled(NodeId id) {
    const Node& n = graph_.node(id);
    const bool first = is_negative_constant(n.args[0]);
    return literal(-graph_.node(n.args[first ? 0 : 1]).value, scalar_) + " * " + operand(n.args[first ? 1 : 0], kProduct);
  }

  // Text of `first`, then of `second`, joined by `separator`. operand() registers the loads of
  // the leaves it reaches, and C++ leaves the evaluation order of the operands of + open (g++ and
  // clang differ): two statements fix the order, so the emitted code does not depend on the
  // compiler that built sweepgen.
  std::string in_order(const std::function<std::string()>& first, const std::string& separator,
                       const std::function<std::string()>& second) {
    const std::string left = first();
    return left + separator + second();
  }
  std::string binary(NodeId x, int x_context, const std::string& separator, NodeId y, int y_context) {
    return in_order([&] { return operand(x, x_context); }, separator, [&] { return operand(y, y_context); });
  }

  std::string expression(NodeId id, int) {
    const Node& n = graph_.node(id);
    const NodeId a = n.args[0], b = n.args[1];
    const std::string T = scalar_;
    switch (n.op) {
      case Op::add:
        if (is_negative_constant(b)) return operand(a, kSum) + " - " + literal(-graph_.node(b).value, T);
        if (is_negative_constant(a)) return operand(b, kSum) + " - " + literal(-graph_.node(a).value, T);
        if (is_negative_scaled(b))
          return in_order([&] { return operand(a, kSum); }, " - ", [&] { return negated_scaled(b); });
        if (is_negative_scaled(a))
          return in_order([&] { return operand(b, kSum); }, " - ", [&] { return negated_scaled(a); });
        return binary(a, kSum, " + ", b, kSum + 1);
      case Op::sub:
        if (is_negative_constant(b)) return operand(a, kSum) + " + " + literal(-graph_.node(b).value, T);
        if (is_negative_scaled(b))
          return in_order([&] { return operand(a, kSum); }, " + ", [&] { return negated_scaled(b); });
        return binary(a, kSum, " - ", b, kSum + 1);
      case Op::mul:
        if (graph_.node(b).op == Op::constant) return binary(b, kProduct, " * ", a, kProduct + 1);
        return binary(a, kProduct, " * ", b, kProduct + 1);
      case Op::div: return binary(a, kProduct, " / ", b, kProduct + 1);
      case Op::neg: return "-" + operand(a, kUnary + 1);
      case Op::sin: return "sin_of(" + operand(a, kTernary) + ")";
      case Op::cos: return "cos_of(" + operand(a, kTernary) + ")";
      case Op::abs: return "abs_of(" + operand(a, kTernary) + ")";
      case Op::sqrt: return "sqrt_of(" + operand(a, kTernary) + ")";
      case Op::atan2: return "atan2_of(" + binary(a, kTernary, ", ", b, kTernary) + ")";
      case Op::equilibration_scale: return "equilibration_scale(" + operand(a, kTernary) + ")";
      case Op::min: return "min_of(" + binary(a, kTernary, ", ", b, kTernary) + ")";
      case Op::max: return "max_of(" + binary(a, kTernary, ", ", b, kTernary) + ")";
      case Op::select_greater:
      case Op::select_path: {
        const std::string condition = binary(a, kSum, " > ", b, kSum);
        return condition + " ? " + binary(n.args[2], kSum, " : ", n.args[3], kSum);
      }
      case Op::constant: return literal(n.value, T);
      case Op::input: return local_.at(id);
    }
    return "";
  }

  // Stored values that are not computed here (constants, inputs, earlier results).
  void store_rest() {
    if (stores_.empty()) return;
    std::ostringstream lines;
    for (std::size_t i : f_.fields) {
      const Field& field = trace_.fields[i];
      if (!stores_.count(field.node)) continue;
      const std::string target = field_access(field);
      const Node& n = graph_.node(field.node);
      lines << "  " << store_statement(target, &field, operand(field.node, kTernary), n.op == Op::constant ? &n.value : nullptr)
            << "\n";
    }
    for (NodeId id : f_.carried_out)
      if (stores_.count(id)) {
        const Node& n = graph_.node(id);
        lines << "  "
              << store_statement("state." + plan_.carried_name.at(id), nullptr, operand(id, kTernary),
                                 n.op == Op::constant ? &n.value : nullptr)
              << "\n";
      }
    text_ << "\n  // Values computed before this function, and constants.\n";
    flush_loads();
    text_ << lines.str();
  }

  const symbolic::Trace& trace_;
  const symbolic::Graph& graph_;
  const Plan& plan_;
  const FunctionPlan& f_;
  const model::Chain& chain_;
  const std::string scalar_;
  std::map<NodeId, const Field*> field_of_;
  std::map<NodeId, int> uses_;
  std::map<NodeId, std::string> local_;
  std::map<NodeId, bool> declared_;
  std::map<NodeId, std::string> leaf_source_;
  std::set<NodeId> loaded_;
  std::vector<NodeId> pending_loads_;
  std::map<NodeId, std::vector<std::pair<std::string, const Field*>>> stores_;  // target, field (or carried)
  std::ostringstream text_;
  OpCount ops_;                       // outside the path blocks
  OpCount taken_extra_, worst_extra_;  // inside them: the taken branches, the costlier ones
  std::string indent_ = "  ";
  std::set<NodeId> hoisted_;  // find_hoisted
  std::set<NodeId> split_;    // find_split
  LaneGroups lanes_;
  std::map<std::size_t, std::vector<std::string>> group_locals_;
  int next_vector_ = 0;
  int next_path_ = 0;
  int next_part_ = 1;
  std::string lanes_part_ = "return false";  // where a Batch's lanes part at a (C4) condition
  // find_parts and write_part: where each computed value is written, where each value is read
  // last, and the variables a part declares (name, type, the values they hold) while recording_.
  std::vector<std::size_t> written_at_;
  std::map<NodeId, std::size_t> last_read_;
  struct Declared {
    std::string name, type;
    std::vector<NodeId> nodes;
  };
  std::vector<Declared> declaring_;
  struct HandedOn {
    std::string part, type, name;
  };
  std::vector<HandedOn> handed_on_;  // the values each part hands on, in order
  bool recording_ = false;
  std::vector<NodeId> angles_;               // find_angles: the values whose sin and cos are taken
  std::map<NodeId, std::size_t> angle_index_;  // value -> its index in angles_
  std::map<NodeId, std::size_t> angle_of_;     // sin or cos node -> the index of its value
  bool angles_written_ = false;
  std::size_t vector_expressions_ = 0;
  int next_expression_ = 0;
  int block_body_ = -2;
  std::string block_sweep_, block_array_;
};

}  // namespace

FunctionText write_function(const symbolic::Trace& trace, const Plan& plan, const FunctionPlan& function,
                            const model::Chain& chain, const std::string& scalar) {
  return Writer(trace, plan, function, chain, scalar).write();
}

}  // namespace sweepgen::emit
