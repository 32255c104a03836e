// Real-time guarantees of the generated code (README, "Real-time use"), proven on the code itself:
//   - no heap allocation: this binary replaces operator new/delete (every variant) and the
//     malloc family, counts every call while the generated functions run on random inputs, and
//     asserts zero (and that the counter does count: AllocationCounter.SeesAnAllocation);
//   - no data-dependent control flow: the committed generated/*.cpp are scanned: every `for`
//     has a compile-time bound, there is no while/do/goto/switch/recursion, no allocation or
//     exception keyword, and the only `if` is the status-flag accumulation of the template;
//   - bounded stack: the scene libraries are compiled with -fstack-usage (tests/CMakeLists.txt,
//     "Hardening" block); every frame is static (no VLA/alloca) and below kFrameBound, and so is
//     the deepest call chain of one solve.
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
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "iiwa14_nc6_solver.hpp"
#include "panda_nc6_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/flat_problem.hpp"
#include "support/generated_check.hpp"

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

// Runs outward, drivers_from_flat + decompose, every solve_<policy> and every
// solve_<policy>_flat of `Api` on kStates random problems of `scene` inside one counted region.
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

// The file's lines with // comments and #include lines blanked (the generated code has no block
// comments and no string literals; both are asserted, and the includes are checked on their own).
std::vector<std::string> code_lines(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    const auto comment = line.find("//");
    if (comment != std::string::npos) line.erase(comment);
    if (line.rfind("#", 0) == 0) line.clear();  // includes and the preprocessor lines checked apart
    lines.push_back(line);
  }
  return lines;
}

// A function definition of the generated .cpp: name and its lines (signature to closing brace).
struct Function {
  std::string name;
  std::size_t first = 0, last = 0;  // line indices
};

std::vector<Function> functions(const std::vector<std::string>& lines) {
  static const std::regex definition(R"(^(?:SWEEPGEN_FLAT_SOLVE )?(void|Drivers) (\w+)\()");
  std::vector<Function> result;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (std::regex_search(lines[i], m, definition)) result.push_back({m[2], i, i});
    if (!result.empty() && lines[i] == "}" && result.back().last == result.back().first) result.back().last = i;
  }
  return result;
}

TEST(GeneratedSources, ExistAndIncludeOnlyTheirHeaderAndMath) {
  const auto files = generated_sources();
  ASSERT_GE(files.size(), 8u);
  for (const auto& file : files) {
    std::ifstream in(file);
    const std::string own = "#include \"" + file.stem().string() + ".hpp\"";
    // Besides the includes, the template's few preprocessor lines: the GCC-only attribute that
    // fuses a flat solve, the diagnostic pragma around the (C4) path blocks and the choice of the
    // lanes' type (the vector extension, or the array fallback).
    static const std::set<std::string> preprocessor = {
        "#if defined(__GNUC__) && !defined(SWEEPGEN_SCALAR_LANES)",
        "#if defined(__GNUC__) && !defined(__clang__)", "#pragma GCC diagnostic push",
        "#pragma GCC diagnostic ignored \"-Wmaybe-uninitialized\"", "#pragma GCC diagnostic pop", "#endif", "#else",
        "#if defined(__GNUC__)", "#define SWEEPGEN_FLAT_SOLVE __attribute__((flatten))", "#define SWEEPGEN_FLAT_SOLVE",
        "#undef SWEEPGEN_FLAT_SOLVE"};
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("#", 0) != 0) continue;
      // <cstdint>, <cstring>, <type_traits>: the equilibration helper's bit copy of one
      // scalar (std::memcpy of 4 or 8 bytes, no allocation).
      EXPECT_TRUE(line == own || line == "#include <algorithm>" || line == "#include <cmath>" ||
                  line == "#include <limits>" || line == "#include <cstdint>" || line == "#include <cstring>" ||
                  line == "#include <type_traits>" || preprocessor.count(line))
          << file << ": " << line;
    }
    const auto fs = functions(code_lines(file));
    EXPECT_GE(fs.size(), 5u) << file;  // outward, decompose, drivers_from_flat, a solve and its flat form
    for (const auto& f : fs) EXPECT_GT(f.last, f.first) << file << ": " << f.name << " has no closing brace";
  }
}

TEST(GeneratedSources, EveryLoopHasACompileTimeBound) {
  // The only loop form: for (int i = 0; i < BOUND; ++i) with BOUND the constexpr dof, nq (a
  // floating base's q) or constraints of the header, or an integer literal (6 for spatial vectors, the run-time
  // directions and 6 per constraint set of a scene with listed sets); the body never writes
  // the counter.
  static const std::regex loop(R"(\bfor \(int (\w+) = 0; (\w+) < (dof|nq|constraints|[1-9][0-9]*); \+\+(\w+)\)(?: (.*))?$)");
  static const std::regex any_for(R"(\bfor\b)");
  long loops = 0;
  for (const auto& file : generated_sources()) {
    const auto lines = code_lines(file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (!std::regex_search(lines[i], any_for)) continue;
      std::smatch m;
      ASSERT_TRUE(std::regex_search(lines[i], m, loop)) << file << ":" << i + 1 << ": " << lines[i];
      const std::string counter = m[1];
      EXPECT_EQ(m[2], counter) << file << ":" << i + 1;
      EXPECT_EQ(m[4], counter) << file << ":" << i + 1;
      // The body: the rest of the line, or the next line when the header ends the line.
      const std::string body = m[5].str().empty() && i + 1 < lines.size() ? lines[i + 1] : m[5].str();
      const std::regex writes_counter("(\\+\\+|--)\\s*" + counter + "\\b|\\b" + counter +
                                      "\\s*(\\+\\+|--|[-+*/%&|^]?=[^=])");
      EXPECT_FALSE(std::regex_search(body, writes_counter)) << file << ":" << i + 1 << ": " << body;
      ++loops;
    }
  }
  std::cout << loops << " loops, every one bounded by dof, constraints or a literal\n";
  EXPECT_GT(loops, 0);
}

TEST(GeneratedSources, HaveNoUnboundedOrHiddenControlFlow) {
  // Keywords that would mean a data-dependent loop, a jump, an allocation, an exception or
  // hidden state.
  static const std::regex forbidden(
      R"(\b(while|do|goto|switch|case|break|continue|throw|try|catch|new|delete|malloc|calloc|realloc|free|alloca|setjmp|longjmp|static|thread_local|virtual|asm|typeid|dynamic_cast)\b|"|/\*)");
  // `else` only as the second branch of a (C4) path block (BranchOnlyThroughSelects).
  static const std::regex any_else(R"(\belse\b)");
  for (const auto& file : generated_sources()) {
    const auto lines = code_lines(file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (std::regex_search(lines[i], any_else)) {
        EXPECT_EQ(lines[i], "  } else {") << file << ":" << i + 1;
      }
      std::smatch m;
      EXPECT_FALSE(std::regex_search(lines[i], m, forbidden)) << file << ":" << i + 1 << ": '" << m.str() << "' in "
                                                              << lines[i];
    }
  }
}

const std::string kEquilibrationReturn = "  return x > T(0) && x <= std::numeric_limits<T>::max() ? scale : T(0);";

TEST(GeneratedSources, BranchOnlyThroughSelects) {
  // Data-dependent choices (pivot test, saturation, largest-energy selection) are ?: selects
  // and std::min/max, which compile to branch-free conditional moves. The one `if` is the
  // template's status-flag accumulation after every solve,
  //     for (int i = 0; i < dof; ++i)
  //       if (out.saturated[i]) status |= status_saturated;
  // a fixed-count loop whose only effect is to OR one bit (no early exit, no work skipped).
  // The only returns are drivers_from_flat's `return drivers;`, the one of the template's
  // equilibration_scale helper (a select between the power of two and 0) and those of the
  // portable Lanes2's operators (a lane, or the array the operator filled lane by lane in a loop
  // of literal bound: EveryLoopHasACompileTimeBound). The other `if`s are the
  // path blocks of (C4) (docs/derivation.md): `if (a > b) {` (a a name or a literal) straight-line code `} else {`
  // straight-line code `}`, at the function's top level, each branch bounded like the rest.
  static const std::regex any_if(R"(\bif\b)");
  static const std::regex path_if(R"(^  if \([\w.]+ > \w+\) \{ *$)");  // a name or a literal (C4: 1.0 > bound)
  static const std::regex status_if(R"(^    if \(out\.saturated\[i\]\) status \|= status_saturated;$)");
  static const std::regex loop_header(R"(^  for \(int i = 0; i < dof; \+\+i\)$)");
  static const std::regex any_return(R"(\breturn\b)");
  static const std::regex lane_operator_return(
      R"(^  (Scalar operator\[\]\(int l\) const \{ return lane\[l\]; \}|friend Lanes2 operator[-+*/]\((Lanes2|Scalar) [as], Lanes2 b\) \{ for \(int l = 0; l < 2; \+\+l\) [ab]\.lane\[l\] = [^;{}]*; return [ab]; \}|friend Lanes2 operator[-+*/]\(Lanes2 a(, Scalar s)?\) \{ for \(int l = 0; l < 2; \+\+l\) a\.lane\[l\] = [^;{}]*; return a; \})$)");
  long ifs = 0, path_ifs = 0, selects = 0, returns = 0;
  for (const auto& file : generated_sources()) {
    const auto lines = code_lines(file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      selects += std::count(lines[i].begin(), lines[i].end(), '?');
      if (std::regex_search(lines[i], any_return)) {
        EXPECT_TRUE(lines[i] == "  return drivers;" || lines[i] == kEquilibrationReturn ||
                    std::regex_search(lines[i], lane_operator_return))
            << file << ":" << i + 1 << ": " << lines[i];
        ++returns;
      }
      if (!std::regex_search(lines[i], any_if)) continue;
      if (std::regex_search(lines[i], path_if)) {
        ++path_ifs;
        std::size_t j = i + 1;  // its else at the same depth, then its end
        while (j < lines.size() && lines[j] != "  } else {") {
          EXPECT_EQ(lines[j].rfind("  }", 0), std::string::npos) << file << ":" << j + 1 << ": a path block ends without else";
          EXPECT_FALSE(std::regex_search(lines[j], any_if)) << file << ":" << j + 1 << ": a branch in a path block";
          ++j;
        }
        ASSERT_LT(j, lines.size()) << file << ":" << i + 1;
        continue;
      }
      ++ifs;
      EXPECT_TRUE(std::regex_search(lines[i], status_if)) << file << ":" << i + 1 << ": " << lines[i];
      EXPECT_TRUE(i > 0 && std::regex_search(lines[i - 1], loop_header)) << file << ":" << i + 1;
    }
  }
  std::cout << selects << " ?: selects; " << ifs << " status-flag ifs; " << path_ifs << " path blocks; " << returns
            << " returns\n";
  EXPECT_GT(path_ifs, 0);
  EXPECT_GT(selects, 0);
}

TEST(GeneratedSources, CallOnlyEachOtherAcyclicallyAndConstantTimeMath) {
  // Every call in a function body is to another generated function (the call graph has no
  // cycle: no recursion), or to constant-time math: std::sin/cos/abs/min/max, Scalar(x),
  // static_cast<Scalar>, static_cast<int> (a count stored in the Solution) and the template's equilibration_scale (the exponent field of one value,
  // BranchOnlyThroughSelects checks its one return).
  static const std::regex call(R"(([A-Za-z_][A-Za-z0-9_:<>]*)\s*\()");
  static const std::set<std::string> math = {"std::sin",        "std::cos",        "std::abs",        "std::min<double>",
                                             "std::max<double>", "std::min<float>", "std::max<float>", "Scalar",
                                             "static_cast<Scalar>", "static_cast<int>", "equilibration_scale"};
  for (const auto& file : generated_sources()) {
    const auto lines = code_lines(file);
    const auto fs = functions(lines);
    std::set<std::string> defined;
    for (const auto& f : fs) defined.insert(f.name);
    std::map<std::string, std::set<std::string>> callees;
    for (const auto& f : fs) {
      auto& out = callees[f.name];
      for (std::size_t i = f.first + 1; i <= f.last; ++i) {
        for (std::sregex_iterator it(lines[i].begin(), lines[i].end(), call), end; it != end; ++it) {
          const std::string name = (*it)[1];
          if (name == "for" || name == "if") continue;
          if (defined.count(name)) {
            out.insert(name);
          } else {
            EXPECT_TRUE(math.count(name)) << file << ":" << i + 1 << ": call to " << name;
          }
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

// ---- Stack use ---------------------------------------------------------------------------------

// Bound on each function's frame and on the deepest call chain of one solve (README,
// "Real-time use"); measured at most ~20 KiB (iiwa14_nc6 flat solve with `expose: all`).
[[maybe_unused]] constexpr long kFrameBound = 64 * 1024;  // unused where the test is skipped

struct Frame {
  std::string function;  // qualified name, without the parameter list
  long bytes = 0;
  std::string qualifier;
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
  // "file:line:column:[return type ]qualified::name[(parameters)][ [with T = ...]]<TAB>bytes<TAB>qualifier";
  // a name may hold "{anonymous}" (the template's helper in its unnamed namespace).
  static const std::regex su_line(R"(^[^\t]*:\d+:\d+:(?:[\w:]+ )?([\w:{}]+)(?:\([^\t]*\))?(?: \[with [^\t]*\])?\t(\d+)\t(\S+)$)");
  long worst_frame = 0, worst_chain = 0;
  std::string worst_frame_name, worst_chain_name;
  for (const auto& file : files) {
    std::ifstream in(file);
    ASSERT_TRUE(in) << file << " (built with -fstack-usage by the scene library targets)";
    std::map<std::string, Frame> frames;  // by qualified name
    for (std::string line; std::getline(in, line);) {
      std::smatch m;
      ASSERT_TRUE(std::regex_search(line, m, su_line)) << file << ": " << line;
      Frame f{m[1], std::stol(m[2]), m[3]};
      EXPECT_EQ(f.qualifier, "static") << file << ": " << f.function << " has a dynamic frame";
      EXPECT_LT(f.bytes, kFrameBound) << file << ": " << f.function;
      if (f.bytes > worst_frame) worst_frame = f.bytes, worst_frame_name = f.function;
      frames[f.function] = f;
    }
    ASSERT_FALSE(frames.empty()) << file;
    std::cout << std::filesystem::path(file).filename().string() << ":\n";
    for (const auto& [name, f] : frames) {
      // One solve: a flat solve calls outward, drivers_from_flat, decompose and its solve_<policy>
      // (one after the other); the structured API calls them from the caller. libm's sin/cos
      // add a few hundred bytes beyond.
      long chain = f.bytes;
      const auto flat = name.rfind("_flat");
      const bool flat_solve = flat != std::string::npos && flat + 5 == name.size() &&
                              name.compare(name.rfind("::") + 2, 6, "solve_") == 0;
      if (flat_solve) {
        const std::string prefix = name.substr(0, name.rfind("::") + 2);
        const std::string solve = name.substr(0, flat);
        long deepest = 0;
        for (const std::string& callee : {prefix + "outward", prefix + "drivers_from_flat", prefix + "decompose", solve}) {
          const auto c = frames.find(callee);
          EXPECT_NE(c, frames.end()) << callee;
          if (c != frames.end()) deepest = std::max(deepest, c->second.bytes);
        }
        chain += deepest;
        EXPECT_LT(chain, kFrameBound) << name << " with its deepest callee";
      }
      std::cout << "  " << f.bytes << " B " << name;
      if (chain != f.bytes) std::cout << " (" << chain << " B with its deepest callee)";
      std::cout << "\n";
      if (chain > worst_chain) worst_chain = chain, worst_chain_name = name;
    }
  }
  std::cout << "largest frame " << worst_frame << " B (" << worst_frame_name << "); deepest solve " << worst_chain
            << " B (" << worst_chain_name << "); bound " << kFrameBound << " B\n";
#endif
}

}  // namespace
