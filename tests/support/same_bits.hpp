// Two builds of one generated solver compared bit for bit (optimisation levels, the lanes' array
// fallback): a flat entry point's output for one input, and whether two outputs are equal bits.
#pragma once

#include <cstddef>
#include <cstring>
#include <vector>

namespace sweepgen::test {

// `function`'s output (of `size` values) for the flat input `in`.
template <class Function, class T>
std::vector<T> flat_output(Function function, const std::vector<T>& in, std::size_t size) {
  std::vector<T> out(size);
  function(in.data(), out.data());
  return out;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace sweepgen::test
