// Real-time guarantees of the generated code (docs/generated-code.md, "Real-time use"), proven on the code itself:
//   - no heap allocation: this binary replaces operator new/delete (every variant) and the
//     malloc family, counts every call while the generated functions run on random inputs, and
//     asserts zero (and that the counter does count: AllocationCounter.SeesAnAllocation);
//   - no data-dependent control flow: the committed generated/*.cpp are scanned: every `for`
//     has a compile-time bound (a batch entry's loop over its states aside), there is no
//     while/do/goto/switch/recursion, no allocation or exception keyword, and the only `if`s are
//     the (C4) path blocks and a flat solve's tests of its stages (which fail only in lanes);
//   - bounded stack: the scene libraries are compiled with -fstack-usage (tests/CMakeLists.txt,
//     "Hardening" block); every frame is static (no VLA/alloca) and below kFrameBound, and so is
//     the deepest call chain of one solve; a batch entry point's, below kBatchFrameBound.
// No exceptions: tests/realtime/noexcept_solve.cpp (ctest realtime_no_exceptions) builds the
// generated sources with -fno-exceptions -fno-rtti -Werror.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "iiwa14_nc6_solver.hpp"
#include "panda_nc6_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/flat_problem.hpp"
#include "support/generated_check.hpp"
#include "support/text_pattern.hpp"

// ---- Allocation counter ---------------------------------------------------------------------
// Counts are global (gtest runs the tests on one thread); counting is on only inside
// CountedRegion.

#if defined(__SANITIZE_ADDRESS__)
#define SWEEPGEN_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SWEEPGEN_ASAN 1
#endif
#endif

namespace {

std::atomic<bool> g_counting{false};
std::atomic<long> g_new_calls{0}, g_delete_calls{0}, g_malloc_calls{0}, g_free_calls{0};

inline void count(std::atomic<long>& counter) {
  if (g_counting.load(std::memory_order_relaxed)) counter.fetch_add(1, std::memory_order_relaxed);
}

struct Counts {
  long new_calls, delete_calls, malloc_calls, free_calls;
  long total() const { return new_calls + delete_calls + malloc_calls + free_calls; }
};

std::ostream& operator<<(std::ostream& os, const Counts& c) {
  return os << "operator new " << c.new_calls << ", operator delete " << c.delete_calls << ", malloc family "
            << c.malloc_calls << ", free " << c.free_calls;
}

// Runs `body` with counting on; returns what it counted.
Counts counted(const std::function<void()>& body) {
  const Counts before{g_new_calls, g_delete_calls, g_malloc_calls, g_free_calls};
  g_counting = true;
  body();
  g_counting = false;
  return {g_new_calls - before.new_calls, g_delete_calls - before.delete_calls, g_malloc_calls - before.malloc_calls,
          g_free_calls - before.free_calls};
}

}  // namespace

#ifdef SWEEPGEN_ASAN
// Under AddressSanitizer the malloc family belongs to the sanitizer's allocator; its hooks see
// every malloc/calloc/realloc/aligned allocation and free of the process.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, std::size_t),
                                                          void (*free_hook)(const volatile void*));
namespace {
void malloc_hook(const volatile void*, std::size_t) { count(g_malloc_calls); }
void free_hook(const volatile void*) { count(g_free_calls); }
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(malloc_hook, free_hook);
}  // namespace
#else
// Replacements of the C allocation functions, forwarding to glibc's own implementations.
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);

void* malloc(std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_realloc(p, size);
}
void free(void* p) noexcept {
  count(g_free_calls);
  __libc_free(p);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_memalign(alignment, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  count(g_malloc_calls);
  if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) return EINVAL;
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_valloc(size);
}
void* pvalloc(std::size_t size) noexcept {
  count(g_malloc_calls);
  return __libc_pvalloc(size);
}
}  // extern "C"
#endif

// Every replaceable global allocation and deallocation function ([new.delete]).
namespace {
void* allocate(std::size_t size) {
  count(g_new_calls);
  void* p = std::malloc(size == 0 ? 1 : size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* allocate(std::size_t size, std::align_val_t alignment) {
  count(g_new_calls);
  const std::size_t a = std::max(static_cast<std::size_t>(alignment), sizeof(void*));
  void* p = nullptr;
  if (posix_memalign(&p, a, size == 0 ? 1 : size) != 0) throw std::bad_alloc();
  return p;
}
void deallocate(void* p) noexcept {
  count(g_delete_calls);
  std::free(p);
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t a) { return allocate(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return allocate(n, a); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate(n, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate(n, a);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { deallocate(p); }
void operator delete[](void* p) noexcept { deallocate(p); }
void operator delete(void* p, std::size_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::size_t) noexcept { deallocate(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { deallocate(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { deallocate(p); }
void operator delete(void* p, std::align_val_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::align_val_t) noexcept { deallocate(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { deallocate(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { deallocate(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { deallocate(p); }

namespace {

using sweepgen::test::Match;
using sweepgen::test::Pattern;
using sweepgen::test::source_path;

// Keeps a pointer observable so that the compiler cannot elide the allocation behind it.
void* volatile g_sink = nullptr;

// ---- The counter counts ---------------------------------------------------------------------

TEST(AllocationCounter, SeesAnAllocation) {
  const Counts vector_counts = counted([] {
    std::vector<double> v(100, 1.0);
    g_sink = v.data();
  });
  std::cout << "std::vector<double>(100): " << vector_counts << "\n";
  EXPECT_GE(vector_counts.new_calls, 1);
  EXPECT_GE(vector_counts.delete_calls, 1);
  EXPECT_GE(vector_counts.malloc_calls, 1);  // operator new allocates through malloc
  EXPECT_GE(vector_counts.free_calls, 1);

  const Counts malloc_counts = counted([] {
    void* p = std::malloc(64);
    g_sink = p;
    std::free(p);
  });
  EXPECT_EQ(malloc_counts.malloc_calls, 1);
  EXPECT_EQ(malloc_counts.free_calls, 1);

  const Counts aligned_counts = counted([] {
    struct alignas(64) Wide {
      double v[8];
    };
    auto* w = new Wide;
    g_sink = w;
    delete w;
  });
  EXPECT_EQ(aligned_counts.new_calls, 1);
  EXPECT_EQ(aligned_counts.delete_calls, 1);
  EXPECT_EQ(counted([] {}).total(), 0);
}

// ---- Zero allocations in the generated functions ----------------------------------------------

SWEEPGEN_GENERATED_API(PandaF64, panda_nc6::f64);
SWEEPGEN_GENERATED_API(PandaF32, panda_nc6::f32);
SWEEPGEN_GENERATED_API(IiwaF64, iiwa14_nc6::f64);
SWEEPGEN_GENERATED_API(IiwaF32, iiwa14_nc6::f32);

constexpr int kStates = 200;

// Runs outward, drivers_from_flat + decompose, every solve_<policy>, every solve_<policy>_flat and
// every solve_<policy>_batch of `Api` on kStates random problems of `scene` inside one counted region.
template <class Api>
void expect_no_allocation(const std::string& scene) {
  using Scalar = typename Api::Scalar;
  const auto s = sweepgen::scene::load_scene(source_path(scene));
  const auto chain = sweepgen::scene::load_scene_chain(s);
  const int n = static_cast<int>(chain.dof());
  const int nc = static_cast<int>(s.layout.constraints);
  sweepgen::test::RandomProblem random(7);
  std::vector<std::vector<Scalar>> inputs;
  for (int k = 0; k < kStates; ++k) {
    const auto p = sweepgen::test::random_flat_problem(random, s, chain);
    inputs.emplace_back(p.in.begin(), p.in.end());
    ASSERT_EQ(inputs.back().size(), static_cast<std::size_t>(Api::flat_in_size));
  }
  std::vector<Scalar> out(Api::flat_out_size);
  // The same states for the batch entry points, in rows of kStates values.
  std::vector<Scalar> batch_in(inputs.size() * Api::flat_in_size), batch_out(inputs.size() * Api::flat_out_size);
  for (std::size_t k = 0; k < inputs.size(); ++k)
    for (int i = 0; i < Api::flat_in_size; ++i) batch_in[i * inputs.size() + k] = inputs[k][i];
  // State and Solution are big (iiwa14_nc6 exposes every intermediate): keep them off the stack.
  auto state = std::make_unique<typename Api::State>();
  auto solution = std::make_unique<typename Api::Solution>();
  Scalar checksum = 0;
  int calls = 0;

  const Counts c = counted([&] {
    for (const auto& in : inputs) {
      Api::outward(in.data(), in.data() + n, *state);
      Api::decompose(in.data() + 2 * n, *state);  // drivers_from_flat + decompose
      calls += 3;
      for (const auto& entry : Api::solves) {
        entry.solve(*state, in.data() + Api::flat_in_size - nc, *solution);
        checksum += solution->qdd[n - 1];
        ++calls;
      }
      for (const auto& entry : Api::flat_solves) {
        entry.solve(in.data(), out.data());
        checksum += out[0];
        ++calls;
      }
    }
    for (const auto& entry : Api::batch_solves) {
      entry.solve(kStates, batch_in.data(), batch_out.data());
      checksum += batch_out[0];
      ++calls;
    }
  });
  std::cout << scene << " (" << sizeof(Scalar) * 8 << "-bit): " << calls << " generated calls on " << kStates
            << " random states: " << c << "\n";
  EXPECT_EQ(c.total(), 0) << c;
  EXPECT_TRUE(std::isfinite(checksum));
}

TEST(GeneratedCode, PandaNc6DoubleDoesNotAllocate) { expect_no_allocation<PandaF64>("robots/panda/panda_nc6.yaml"); }
TEST(GeneratedCode, PandaNc6FloatDoesNotAllocate) { expect_no_allocation<PandaF32>("robots/panda/panda_nc6.yaml"); }
TEST(GeneratedCode, Iiwa14Nc6DoubleDoesNotAllocate) { expect_no_allocation<IiwaF64>("robots/iiwa14/iiwa14_nc6.yaml"); }
TEST(GeneratedCode, Iiwa14Nc6FloatDoesNotAllocate) { expect_no_allocation<IiwaF32>("robots/iiwa14/iiwa14_nc6.yaml"); }

// ---- Control flow of the committed generated sources ------------------------------------------

std::vector<std::filesystem::path> generated_sources() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(source_path("generated")))
    if (entry.path().extension() == ".cpp") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The runtime every generated source holds verbatim (templates/lanes.mustache: the lanes' types,
// min/max/abs, sin/cos, the equilibration scale and the batch loops): checked once, apart
// (TheRuntimeIsTheTemplatesAndBoundsItsLoops), and blanked where the rest of a file is checked.
const std::string& runtime_text() {
  static const std::string text = file_text(source_path("templates/lanes.mustache"));
  return text;
}

// Lines with // comments blanked (the generated code has no block comments and no string
// literals; both are asserted), from `text`.
std::vector<std::string> code_lines_of(const std::string& text, bool blank_preprocessor) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    const auto comment = line.find("//");
    if (comment != std::string::npos) line.erase(comment);
    if (blank_preprocessor && line.rfind("#", 0) == 0) line.clear();  // checked apart
    lines.push_back(line);
  }
  return lines;
}

// A generated source's own lines: its runtime's lines blank (it must hold the runtime once,
// verbatim), and its preprocessor lines too where asked.
std::vector<std::string> own_lines(const std::filesystem::path& file, bool blank_preprocessor = true) {
  std::string text = file_text(file);
  const auto at = text.find(runtime_text());
  EXPECT_NE(at, std::string::npos) << file << " does not hold templates/lanes.mustache verbatim";
  if (at != std::string::npos) {
    EXPECT_EQ(text.find(runtime_text(), at + 1), std::string::npos) << file << " holds the runtime twice";
    for (std::size_t i = at; i < at + runtime_text().size(); ++i)
      if (text[i] != '\n') text[i] = ' ';
  }
  // The output set's check (the .cpp's static_asserts of the header's and the .cmake's
  // output_set) is compile time only: no statement of the solver, so no subject of these checks.
  for (std::size_t at = text.find("static_assert("); at != std::string::npos; at = text.find("static_assert(", at + 1)) {
    const std::size_t end = text.find(';', at);
    for (std::size_t i = at; i < end && i < text.size(); ++i)
      if (text[i] != '\n') text[i] = ' ';
  }
  return code_lines_of(text, blank_preprocessor);
}

// A function definition of the generated .cpp: name and its lines (signature to closing brace).
struct Function {
  std::string name;
  std::size_t first = 0, last = 0;  // line indices (last 0: not closed)
};

std::vector<Function> functions(const std::vector<std::string>& lines) {
  static const Pattern definition(
      R"(^(?:\[\[maybe_unused\]\] )?(?:SWEEPGEN_FLAT_SOLVE )?(?:SWEEPGEN_HD )?(?:SWEEPGEN_INLINE )?(void|bool|int|Drivers|typename Arrays<S>::Drivers|FlatDrivers<S>|FlatDrivers<Scalar>) (\w+)\()");
  std::vector<Function> result;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    Match m;
    const auto end = lines[i].find_last_not_of(' ');
    if (end != std::string::npos && lines[i][end] == ';') continue;  // a declaration (an ISA object's entry point)
    if (definition.search(lines[i], m)) {
      // A wrapper defined on its line (`{ <call>; }`) ends there.
      const bool one_line = lines[i].find('{') != std::string::npos && lines[i].find_last_not_of(' ') == lines[i].rfind('}');
      result.push_back({m[2], i, one_line ? i : 0});
      continue;
    }
    if (!result.empty() && lines[i].rfind("}", 0) == 0 && result.back().last == 0) result.back().last = i;
  }
  return result;
}

TEST(GeneratedSources, ExistAndIncludeOnlyTheirHeaderAndMath) {
  const auto files = generated_sources();
  ASSERT_GE(files.size(), 8u);
  for (const auto& file : files) {
    const std::string own = "#include \"" + file.stem().string() + ".hpp\"";
    // Besides the includes, the template's few preprocessor lines: the GCC-only attribute that
    // fuses a flat solve, the diagnostic pragma around the (C4) path blocks, the choice of the
    // lanes' types (vectors, or arrays), the batch entry points (not in a CUDA build; each an ISA
    // object's, a call of the widest one, or in this object's lanes: the runtime says which), the
    // output set's check against the .cmake snippet's.
    static const std::set<std::string> preprocessor = {
        "#if defined(SWEEPGEN_BATCH_BYTES)", "#if !defined(__CUDACC__)",
        "#if defined(__GNUC__) && !defined(__clang__)", "#pragma GCC diagnostic push",
        "#pragma GCC diagnostic ignored \"-Wmaybe-uninitialized\"", "#pragma GCC diagnostic pop", "#endif", "#else",
        "#if defined(__GNUC__)", "#define SWEEPGEN_FLAT_SOLVE __attribute__((flatten))", "#define SWEEPGEN_FLAT_SOLVE",
        "#undef SWEEPGEN_FLAT_SOLVE", "#if defined(SWEEPGEN_OUTPUT_SET)", "#if defined(SWEEPGEN_BATCH_ISA)", "#if !defined(SWEEPGEN_BATCH_ISA)",
        "#if defined(SWEEPGEN_BATCH_CALLS_V4)", "#if defined(SWEEPGEN_BATCH_CALLS_V3)", "#if defined(SWEEPGEN_BATCH_OWN_LANES)"};
    for (std::string line : own_lines(file, false)) {
      if (line.rfind("#", 0) != 0) continue;
      line.erase(line.find_last_not_of(' ') + 1);  // a trailing comment's place
      // <cstddef>, <cstdint>, <cstring>, <type_traits>: the runtime's sizes, bit copies of one
      // scalar (std::memcpy of 4 or 8 bytes, no allocation) and its float formats.
      EXPECT_TRUE(line == own || line == "#include <cmath>" || line == "#include <cstddef>" ||
                  line == "#include <cstdint>" || line == "#include <cstring>" || line == "#include <type_traits>" ||
                  preprocessor.count(line))
          << file << ": " << line;
    }
    const auto fs = functions(own_lines(file));
    EXPECT_GE(fs.size(), 5u) << file;  // outward, decompose, drivers_from_flat, a solve and its flat form
    for (const auto& f : fs) EXPECT_GE(f.last, f.first) << file << ": " << f.name << " has no closing brace";
  }
}

// The only loop form: for (int i = 0; i < BOUND; ++i) with BOUND one of `bounds`; the body never
// writes the counter. Returns the number of loops.
long expect_bounded_loops(const std::string& where, const std::vector<std::string>& lines, const std::string& bounds) {
  static const Pattern any_for(R"(\bfor\b)");
  const Pattern loop(R"(\bfor \((?:int|std::ptrdiff_t) (\w+) = (?:0|first); (\w+) < ()" + bounds +
                        R"(); \+\+(\w+)\)(?: (.*))?$)");
  long loops = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!any_for.search(lines[i])) continue;
    Match m;
    EXPECT_TRUE(loop.search(lines[i], m)) << where << ":" << i + 1 << ": " << lines[i];
    if (m.empty()) continue;
    const std::string counter = m[1];
    EXPECT_EQ(m[2], counter) << where << ":" << i + 1;
    EXPECT_EQ(m[4], counter) << where << ":" << i + 1;
    // The body: the rest of the line, or the next line when the header ends the line.
    const std::string body = m[5].empty() && i + 1 < lines.size() ? lines[i + 1] : m[5];
    const Pattern writes_counter("(\\+\\+|--)\\s*" + counter + "\\b|\\b" + counter + "\\s*(\\+\\+|--|[-+*/%&|^]?=[^=])");
    EXPECT_FALSE(writes_counter.search(body)) << where << ":" << i + 1 << ": " << body;
    ++loops;
  }
  return loops;
}

TEST(GeneratedSources, EveryLoopHasACompileTimeBound) {
  // BOUND: the constexpr dof, nq (a floating base's q), nv and couplings (coupled <mimic> joints)
  // or constraints of the header, or an integer literal (6 for spatial vectors, the run-time
  // directions and 6 per constraint set of a scene with listed sets, 2 for the lanes of a
  // constraint set's directions).
  long loops = 0;
  for (const auto& file : generated_sources())
    loops += expect_bounded_loops(file.string(), own_lines(file), "dof|nq|nv|couplings|constraints|[1-9][0-9]*");
  std::cout << loops << " loops, every one bounded by a constexpr size of the header or a literal\n";
  EXPECT_GT(loops, 0);
}

TEST(GeneratedSources, TheRuntimeIsTheTemplatesAndBoundsItsLoops) {
  // Its loops run over the lanes of a vector (width, a compile-time constant of its type; by
  // chunks of a vector's width over n values), over the n angles of sincos_each or the in_size and
  // out_size values of a flat row (template arguments), or, in the batch entry points alone, over
  // the groups of a tile (a constant of the vector type) and the states given (rows by tiles of a
  // constant size, and a group's count): a batch call takes time linear in its states, each
  // state's solve is bounded like the scalar one (own_lines checks that every source holds this
  // text verbatim). No loop body writes its counter but the `+=` of its header.
  // The only string literals: the CPU features batch_isa() asks __builtin_cpu_supports for (its
  // argument must be one), blanked before the checks below.
  static const Pattern cpu_feature(R"re(__builtin_cpu_supports\("[a-z0-9]+"\))re");
  const auto lines = code_lines_of(cpu_feature.replace(runtime_text(), "__builtin_cpu_supports()"), true);
  static const Pattern any_for(R"(\bfor\b)");
  static const Pattern loop(
      R"(^ *(?:else )?for \((?:int|std::ptrdiff_t) (\w+) = (?:0|1|first); (\w+) < (width|groups|n|in_size|out_size|count|Lanes<\w+>::width|rows|first \+ count)(?: && first \+ \w+ < n)?; (?:\+\+(\w+)|(\w+) \+= (?:width|tile))\))");
  long loops = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!any_for.search(lines[i])) continue;
    Match m;
    EXPECT_TRUE(loop.search(lines[i], m)) << "templates/lanes.mustache:" << i + 1 << ": " << lines[i];
    if (m.empty()) continue;
    EXPECT_EQ(m[2], m[1]) << "templates/lanes.mustache:" << i + 1;
    EXPECT_EQ(m.matched(4) ? m[4] : m[5], m[1]) << "templates/lanes.mustache:" << i + 1;
    ++loops;
  }
  EXPECT_GE(loops, 10);
  static const Pattern forbidden(
      R"(\b(while|do|goto|switch|case|break|throw|try|catch|new|delete|malloc|calloc|realloc|free|alloca|setjmp|longjmp|thread_local|virtual|asm|typeid|dynamic_cast)\b|"|/\*)");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    Match m;
    EXPECT_FALSE(forbidden.search(lines[i], m)) << "templates/lanes.mustache:" << i + 1 << ": '" << m[0]
                                                            << "' in " << lines[i];
  }
}

TEST(GeneratedSources, HaveNoUnboundedOrHiddenControlFlow) {
  // Keywords that would mean a data-dependent loop, a jump, an allocation, an exception or
  // hidden state.
  static const Pattern forbidden(
      R"(\b(while|do|goto|switch|case|break|continue|throw|try|catch|new|delete|malloc|calloc|realloc|free|alloca|setjmp|longjmp|static|thread_local|virtual|asm|typeid|dynamic_cast)\b|"|/\*)");
  // `else` only as the second branch of a (C4) path block (BranchOnlyThroughSelects), at a
  // function's top level or a part's.
  static const Pattern any_else(R"(\belse\b)");
  static const Pattern path_else(R"(^(  |    )\} else \{$)");
  for (const auto& file : generated_sources()) {
    const auto lines = own_lines(file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (lines[i].find("else") != std::string::npos && any_else.search(lines[i])) {
        EXPECT_TRUE(path_else.matches(lines[i])) << file << ":" << i + 1 << ": " << lines[i];
      }
      Match m;
      EXPECT_FALSE(forbidden.search(lines[i], m)) << file << ":" << i + 1 << ": '" << m[0] << "' in "
                                                              << lines[i];
    }
  }
}

TEST(GeneratedSources, BranchOnlyThroughSelects) {
  // Data-dependent choices (pivot test, saturation, largest-energy selection) are ?: selects
  // and min_of/max_of, which compile to branch-free conditional moves (or blends in lanes). The
  // `if`s are the path blocks of (C4) (docs/derivation.md), at a function's top level or a part's
  // (a long function's lambda of its own, SWEEPGEN_PART, two spaces further in):
  //     const auto path_N = a > b;      (a a name or a literal)
  //     if (Lanes<S>::all(path_N)) {
  //       straight-line code
  //     } else {
  //       if (Lanes<S>::any(path_N)) return false;   (lanes on both paths: never for a scalar;
  //                                                   in a part `return Part_M{};`, its ok false)
  //       straight-line code, or the pivoted path as a lambda called there:
  //       struct Pivoted_M { ... };  const Pivoted_M pivoted = [...]() {
  //         straight-line code  return Pivoted_M{...};  }();  then its values read
  //     }
  // a flat solve's test of its stages' results, `if (!<stage>_of<S>(...)) return false;`
  // (false only from that line), and a part's, `if (!part_M.ok) return false;`. The other returns: `return true;` at a function's end,
  // drivers_from_flat's `return drivers;`, flat_drivers_of's list of pointers into its input
  // (`return {drivers_in, drivers_in + dof, SixRows<S>{drivers_in + dof + 6}};`), the batch entry's
  // call of its lanes, and the lanes' operators (a lane, or the array the operator filled lane by
  // lane in a loop of literal bound). A batch entry point's (and batch_lanes') other `if`s choose
  // the ISA object it hands the whole call to: the same choice on every call, made before any
  // state is read; batch_lanes returns a width.
  static const Pattern any_if(R"(\bif\b)");
  static const Pattern path_condition(R"(^(  |    )const auto (path_\d+) = [\w.]+ > \w+; *$)");
  static const Pattern stage_test(R"(^  if \(!\w+_of<S>\(.*\)\)(?: return false;)?$|^  if \(!part_\d+\.ok\) return false;  $)");
  // A cold lambda's or a part's values handed back (each a name of its own body).
  static const Pattern handed_back(R"(^ +return (Pivoted|Part)_\d+\{(true|[\w]+)?(, \w+)*\};$)");
  static const Pattern isa_choice(R"(^  if \(batch_isa\(\) == ([34])\) return x86_64_v\1::(\w+_batch\(n, in, out\)|batch_lanes\(\));$)");
  static const Pattern any_return(R"(\breturn\b)");
  static const Pattern allowed_return(
      R"(^  return (true|drivers);$|^  return \{(SixRows<S>\{drivers_in[\w +*]*\}|drivers_in[\w +*]*|, )*\};$|^SWEEPGEN_HD Drivers drivers_from_flat\(const Scalar\* drivers_in\) noexcept \{ return drivers_from_flat_of<Scalar>\(drivers_in\); \}$|^    return false;$|^  if \(!\w+_of<S>\(.*\)\) return false;$|^    if \(Lanes<S>::any\(path_\d+\)\) return false;  $|^      n, in, out, \[\]\(const Batch\* lanes_in, Batch\* lanes_out\) \{ return \w+_flat_of<Batch>\(lanes_in, lanes_out\); \}, &(?:\w+::)?\w+_flat\);$|^  return (Lanes<Batch>::width|1);$|^  if \(!part_\d+\.ok\) return false;  $|^  return \{(SixRows<Scalar>\{drivers\.\w+\[0\]\}|drivers\.\w+|, )*\};$|^  SWEEPGEN_HD S operator\[\]\(int l\) const \{ return lane\[l\]; \}$|^  friend SWEEPGEN_HD LaneArray operator[-+*/]\((LaneArray|T) [as](, (LaneArray|T) [bs])?\) \{ for \(int l = 0; l < 2; \+\+l\) [ab]\.lane\[l\] = [^;{}]*; return [ab]; \}$)");
  long path_blocks = 0, stage_tests = 0, isa_choices = 0, selects = 0, returns = 0;
  for (const auto& file : generated_sources()) {
    const auto lines = own_lines(file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      selects += std::count(lines[i].begin(), lines[i].end(), '?');
      // (Each regex only where the words it needs are on the line: the same answers, faster.)
      const bool has_return = lines[i].find("return") != std::string::npos;
      if (lines[i].find("batch_isa") != std::string::npos && isa_choice.search(lines[i])) {
        ++isa_choices;
        continue;
      }
      if (has_return && handed_back.search(lines[i])) {
        ++returns;
        continue;
      }
      if (has_return && any_return.search(lines[i])) {
        EXPECT_TRUE(allowed_return.search(lines[i])) << file << ":" << i + 1 << ": '" << lines[i] << "'";
        ++returns;
      }
      Match m;
      if (lines[i].find("path_") != std::string::npos && path_condition.search(lines[i], m)) {
        ++path_blocks;
        const std::string indent = m[1], path = m[2];
        ASSERT_LT(i + 1, lines.size());
        EXPECT_EQ(lines[i + 1], indent + "if (Lanes<S>::all(" + path + ")) {") << file << ":" << i + 2;
        std::size_t j = i + 2;  // its else at the same depth, then its end
        while (j < lines.size() && lines[j] != indent + "} else {") {
          EXPECT_EQ(lines[j].rfind(indent + "}", 0), std::string::npos) << file << ":" << j + 1 << ": a path block ends without else";
          EXPECT_FALSE(any_if.search(lines[j])) << file << ":" << j + 1 << ": a branch in a path block";
          ++j;
        }
        ASSERT_LT(j + 1, lines.size()) << file << ":" << i + 1;
        const Pattern lanes_exit(indent + "  if \\(Lanes<S>::any\\(" + path + "\\)\\) return (false|Part_\\d+\\{\\});  ");
        EXPECT_TRUE(lanes_exit.matches(lines[j + 1])) << file << ":" << j + 2 << ": " << lines[j + 1];
        for (std::size_t k = j + 2; k < lines.size() && lines[k] != indent + "}"; ++k)
          EXPECT_FALSE(any_if.search(lines[k])) << file << ":" << k + 1 << ": a branch in a path block";
        i = j + 1;
        continue;
      }
      if (lines[i].find("if") == std::string::npos || !any_if.search(lines[i])) continue;
      EXPECT_TRUE(stage_test.search(lines[i])) << file << ":" << i + 1 << ": " << lines[i];
      ++stage_tests;
    }
  }
  std::cout << selects << " ?: selects; " << path_blocks << " path blocks; " << stage_tests << " stage tests; "
            << isa_choices << " choices of an ISA object; " << returns << " returns\n";
  EXPECT_GT(path_blocks, 0);
  EXPECT_GT(selects, 0);
}

// The calls in a generated function's body (template arguments dropped), but `for`, `if` and
// `operator`, with their line indices.
std::vector<std::pair<std::string, std::size_t>> calls_in(const std::vector<std::string>& lines, const Function& f) {
  static const Pattern call(R"(([A-Za-z_][A-Za-z0-9_:]*(?:<[^()]*>)?(?:::\w+)?)\s*\()");
  static const Pattern template_arguments(R"(<[^()]*>)");
  std::vector<std::pair<std::string, std::size_t>> result;
  for (std::size_t i = f.first + 1; i <= f.last; ++i) {
    if (lines[i].find('(') == std::string::npos) continue;  // no call (the regex needs one), faster
    for (const Match& called : call.all(lines[i])) {
      std::string name = template_arguments.replace(called[1], "");
      if (name != "for" && name != "if" && name != "operator") result.emplace_back(std::move(name), i);
    }
  }
  return result;
}

// The runtime's constant-time math and lane helpers (TheRuntimeIsTheTemplatesAndBoundsItsLoops),
// static_cast and the batch loops: what a generated function may call besides another.
const std::set<std::string> kRuntimeCalls = {
    "sincos_each",  "sincos_of", "sin_of",       "cos_of",        "abs_of",       "min_of",           "max_of", "sqrt_of", "atan2_of",
    "equilibration_scale", "Lanes::all", "Lanes::any",  "Lanes::count", "Lanes::flag",      "Lanes::of",
    "Lanes::value", "Lanes::status_if", "Lanes::raise_if", "static_cast", "solve_in_lanes", "solve_state_by_state",
    "batch_isa"};

TEST(GeneratedSources, CallOnlyEachOtherAcyclicallyAndConstantTimeMath) {
  // Every call in a function body is to another generated function (the call graph has no
  // cycle: no recursion), or to the runtime (kRuntimeCalls), or an ISA object's batch entry point
  // of the same name: that object is this source compiled with SWEEPGEN_BATCH_ISA, where no entry
  // point calls another object (SWEEPGEN_BATCH_CALLS_*), so the call adds no edge.
  static const Pattern isa_object_call(R"(^x86_64_v[34]::(\w+)$)");
  for (const auto& file : generated_sources()) {
    const auto lines = own_lines(file);
    const auto fs = functions(lines);
    std::set<std::string> defined;
    for (const auto& f : fs) defined.insert(f.name);
    std::map<std::string, std::set<std::string>> callees;
    for (const auto& f : fs) {
      auto& out = callees[f.name];
      for (const auto& [name, i] : calls_in(lines, f)) {
        Match isa;
        if (defined.count(name)) {
          out.insert(name);
        } else if (isa_object_call.matches(name, isa)) {
          EXPECT_TRUE(defined.count(isa[1]) && isa[1] == f.name) << file << ":" << i + 1 << ": call to " << name;
        } else {
          EXPECT_TRUE(kRuntimeCalls.count(name)) << file << ":" << i + 1 << ": call to " << name;
        }
      }
    }
    // Depth-first search for a cycle.
    std::map<std::string, int> mark;  // 0 new, 1 on the path, 2 done
    std::function<bool(const std::string&)> cyclic = [&](const std::string& f) {
      if (mark[f] == 1) return true;
      if (mark[f] == 2) return false;
      mark[f] = 1;
      for (const auto& g : callees[f])
        if (cyclic(g)) return true;
      mark[f] = 2;
      return false;
    };
    for (const auto& f : fs) EXPECT_FALSE(cyclic(f.name)) << file << ": " << f.name << " is on a call cycle";
  }
}

TEST(GeneratedSources, TheLaneScenesCallEveryHelperAnySceneCalls) {
  // Only the bundled scenes of SWEEPGEN_BATCH_ISA_SCENES carry batch lanes in this repository's
  // build (cmake/BundledScenes.cmake); the others' batch entry points solve state by state. So that
  // every operation the lanes run is compiled and held to the flat calls all the same, those scenes
  // (their committed sources: SWEEPGEN_BATCH_LANE_SOURCES, comma-separated) must call every runtime
  // helper that any bundled scene's functions call.
  const std::string listed = SWEEPGEN_BATCH_LANE_SOURCES;
  std::set<std::string> in_lanes;
  std::map<std::string, std::string> a_caller;  // helper -> the first source that calls it
  std::size_t lane_sources = 0;
  for (const auto& file : generated_sources()) {
    const std::string name = file.filename().string();
    const bool lanes = ("," + listed + ",").find("," + name + ",") != std::string::npos;
    lane_sources += lanes;
    const auto lines = own_lines(file);
    for (const auto& f : functions(lines))
      for (const auto& [called, i] : calls_in(lines, f)) {
        if (!kRuntimeCalls.count(called)) continue;
        a_caller.emplace(called, name);
        if (lanes) in_lanes.insert(called);
      }
  }
  EXPECT_EQ(lane_sources, static_cast<std::size_t>(std::count(listed.begin(), listed.end(), ',') + 1))
      << "a source of SWEEPGEN_BATCH_LANE_SOURCES (" << listed << ") is not in generated/";
  std::string found;
  for (const auto& [helper, caller] : a_caller) found += " " + helper;
  EXPECT_TRUE(a_caller.count("sqrt_of") && a_caller.count("sincos_each")) << "the helpers found:" << found;
  for (const auto& [helper, caller] : a_caller)
    EXPECT_TRUE(in_lanes.count(helper)) << caller << " calls " << helper << ", which no scene with batch lanes ("
                                        << listed << ") calls: add one that does to SWEEPGEN_BATCH_ISA_SCENES";
}

// ---- Stack use ---------------------------------------------------------------------------------

// Bound on each function's frame and on the deepest call chain of one solve (README,
// "Real-time use"); measured at most ~20 KiB (iiwa14_nc6 flat solve with `expose: all`).
[[maybe_unused]] constexpr long kFrameBound = 64 * 1024;  // unused where the test is skipped
// A batch entry point's (and its lanes' stages', inlined or called): a State and a Solution of one
// vector of states, so up to its lanes / 2 times a baseline build's (8 floats at x86-64-v3, 16 at
// v4): measured at most ~69 KiB (dual_panda_box f64 at v3 with its decompose; docs/generated-code.md).
[[maybe_unused]] constexpr long kBatchFrameBound = 256 * 1024;

struct Frame {
  std::string function;  // qualified name, without the parameter list
  long bytes = 0;
  std::string qualifier;
  bool lanes = false;  // an instance for a Batch (S a vector type), not for the scalar
};

TEST(GeneratedCode, StackFramesAreStaticAndBounded) {
#if defined(SWEEPGEN_ASAN)
  GTEST_SKIP() << "measured in the build without sanitizers: AddressSanitizer's redzones enlarge every frame";
#elif !defined(SWEEPGEN_STACK_USAGE_FILES)
  GTEST_SKIP() << "the compiler does not support -fstack-usage";
#else
  std::vector<std::string> files;
  {
    std::ifstream list(SWEEPGEN_STACK_USAGE_FILES);
    ASSERT_TRUE(list) << SWEEPGEN_STACK_USAGE_FILES;
    for (std::string object; std::getline(list, object);)
      if (!object.empty()) files.push_back(object.substr(0, object.rfind('.')) + ".su");  // X.cpp.o -> X.cpp.su
  }
  ASSERT_GE(files.size(), 8u);
  // "file:line:column:[return type ]qualified::name[(parameters)][ [with T = ...]]<TAB>bytes<TAB>qualifier"
  // (a return type may name a template's member type: typename ns::{anonymous}::Arrays<S>::Drivers; a
  // batch entry's lambda, which its lanes' solve is inlined into, counts as the entry);
  // a name may hold "{anonymous}" (the template's helper in its unnamed namespace).
  static const Pattern su_line(R"(^[^\t]*:\d+:\d+:(?:[^\t(]* )?([\w:{}]+)(?:\([^\t]*?\)(?:::<lambda\([^\t]*\)>)?)?(?: \[with (?:S = ([^;\]\t]*))?[^\t]*\])?\t(\d+)\t(\S+)$)");
  // A part's lambda (SWEEPGEN_PART), called from its function, or a pivoted path's where the
  // compiler did not inline it (one in a part: called from the part):
  // "file:line:column:function<template arguments>(parameters)::<lambda()>[::<lambda()>]<TAB>bytes<TAB>qualifier".
  static const Pattern lambda_line(R"(^[^\t]*:\d+:\d+:([\w:{}]+)(?:<((?:__vector\(\d+\) )?\w+)[^\t]*)?\([^\t]*\)((?:::<lambda\(\)>)+)\t(\d+)\t(\S+)$)");
  long worst_frame = 0, worst_chain = 0, worst_batch = 0;
  std::string worst_frame_name, worst_chain_name, worst_batch_name;
  for (const auto& file : files) {
    std::ifstream in(file);
    ASSERT_TRUE(in) << file << " (built with -fstack-usage by the scene library targets)";
    const bool isa_object = file.find("/sweepgen_batch/") != std::string::npos;
    std::map<std::string, Frame> frames;  // by qualified name
    // By function and instance (scalar or lanes): its largest frame, and its largest lambda frame
    // at each depth (those at one depth run one at a time).
    std::map<std::pair<std::string, bool>, long> instances;
    std::map<std::pair<std::string, bool>, std::map<std::size_t, long>> lambdas;
    for (std::string line; std::getline(in, line);) {
      Match m;
      const bool lambda = lambda_line.search(line, m);
      ASSERT_TRUE(lambda || su_line.search(line, m)) << file << ": " << line;
      const std::size_t depth = lambda ? m[3].length() / std::string("::<lambda()>").size() : 0;
      Frame f{m[1], std::stol(m[lambda ? 4 : 3]), m[lambda ? 5 : 4], m[2].rfind("__vector", 0) == 0};
      // An ISA object (sweepgen_batch/) may realign its frame to its vectors' 32 or 64 bytes, beyond
      // the ABI's 16: GCC then says "dynamic,bounded", the size an upper bound known at compile
      // time. Plain "dynamic" (a VLA, alloca) is refused everywhere.
      EXPECT_TRUE(f.qualifier == "static" || (isa_object && f.qualifier == "dynamic,bounded"))
          << file << ": " << f.function << " has a " << f.qualifier << " frame";
      const bool batch = f.lanes || f.function.find("_batch") != std::string::npos;
      EXPECT_LT(f.bytes, batch ? kBatchFrameBound : kFrameBound) << file << ": " << f.function;
      if (f.bytes > worst_frame) worst_frame = f.bytes, worst_frame_name = f.function;
      if (lambda) {
        long& largest = lambdas[{f.function, f.lanes}][depth];
        largest = std::max(largest, f.bytes);
        continue;
      }
      long& instance = instances[{f.function, f.lanes}];
      instance = std::max(instance, f.bytes);
      // A function template's instances (a scalar's and a Batch's) share a name: the larger frame.
      if (frames[f.function].bytes <= f.bytes) frames[f.function] = f;
    }
    ASSERT_FALSE(frames.empty()) << file;
    std::cout << std::filesystem::path(file).filename().string() << ":\n";
    for (const auto& [name, f] : frames) {
      // One solve: a flat solve calls the stages' functions outward_of, drivers_from_flat_of,
      // decompose_of and its solve_<policy>_of (one after the other, each inlined where the file is
      // fused), the structured API's functions call one each. libm's sin/cos add a few hundred
      // bytes beyond.
      // An instance's frame (none where it is inlined) with its largest lambda's at each depth
      // (called from it, so on the stack beside it).
      const auto with_lambda = [&](const std::string& function, bool lanes) {
        const auto i = instances.find({function, lanes});
        long bytes = i == instances.end() ? 0 : i->second;
        if (const auto l = lambdas.find({function, lanes}); l != lambdas.end())
          for (const auto& [depth, largest] : l->second) bytes += largest;
        return bytes;
      };
      long chain = with_lambda(name, f.lanes);
      // A flat solve or a batch entry point (its lanes' flat solve inlined into it) of a solve or
      // of the derivatives: the stages it calls, and their lambdas.
      const std::string stage = name.substr(name.rfind("::") + 2);
      const auto suffix = stage.rfind('_');
      const bool entry = suffix != std::string::npos && (stage.substr(suffix) == "_flat" || stage.substr(suffix) == "_batch") &&
                         (stage.rfind("solve_", 0) == 0 || stage.rfind("derivatives_", 0) == 0);
      if (entry) {
        const std::string prefix = name.substr(0, name.rfind("::") + 2) + "{anonymous}::";
        // A batch entry point is in the ISA's namespace, its stages in the variant's.
        const std::string stages = prefix.find("::x86_64_v") == std::string::npos
                                       ? prefix
                                       : prefix.substr(0, prefix.find("::x86_64_v") + 2) + "{anonymous}::";
        const std::string own = stages + stage.substr(0, suffix) + "_of";
        long deepest = 0;
        const bool lanes = stage.substr(suffix) == "_batch";  // the stages' Batch instances
        for (const std::string& callee : {stages + "outward_of", stages + "drivers_from_flat_of", stages + "decompose_of", own})
          deepest = std::max(deepest, with_lambda(callee, lanes));
        chain += deepest;
        EXPECT_LT(chain, lanes ? kBatchFrameBound : kFrameBound) << name << " with its deepest callee";
      }
      std::cout << "  " << f.bytes << " B " << name;
      if (chain != f.bytes) std::cout << " (" << chain << " B with its deepest callee)";
      std::cout << "\n";
      if (entry && stage.substr(suffix) == "_batch") {
        if (chain > worst_batch) worst_batch = chain, worst_batch_name = name;
      } else if (chain > worst_chain) {
        worst_chain = chain, worst_chain_name = name;
      }
    }
  }
  std::cout << "largest frame " << worst_frame << " B (" << worst_frame_name << "); deepest solve " << worst_chain
            << " B (" << worst_chain_name << "); bound " << kFrameBound << " B; deepest batch entry point " << worst_batch
            << " B (" << worst_batch_name << "), bound " << kBatchFrameBound << " B\n";
#endif
}

}  // namespace
