// One generated scene's kernels on a GPU, timed and checked (bench/gpu/run.sh builds it once per
// scene: nvcc -DSWEEPGEN_GPU_SOURCE='"<stem>.cu"' -DSWEEPGEN_GPU_NAMESPACE=<namespace>
// [-DSWEEPGEN_GPU_HAS_F32] [-DSWEEPGEN_GPU_HAS_DERIVATIVES], with the scene's generated files on
// the include path). For each entry point (the original policy's solve, and its derivatives where
// the scene has them; double, and float where the scene has it) and each batch size n:
//   - the kernel alone (states already on the device: <entry>_cuda), the median of 9 launches;
//   - the same with the copies, from pinned host memory (cudaMallocHost) and back, one stream;
//   - states per second of each;
// then the GPU's outputs against the host's (the same generated functions, compiled for the CPU by
// nvcc's host compiler) on `check` states: the largest difference relative to max(1, |output|),
// and the states whose status words differ; and the first `sample` of those states of the double
// solve written to <sample file>, a line per state, its flat input then the GPU's flat output in
// hex floats, for `sweepgen report --scene <scene> --judge <sample file>` to judge against the
// binary128 referee on a machine with the project built (bench/gpu/run.sh says how). One line per
// entry and size, "gpu: ...", the columns of bench/README.md, "GPU"; exit 1 on a CUDA error or a
// differing status word.
//   gpu_bench <check> <sample> <sample file> <n>...
#include <cuda_runtime.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include SWEEPGEN_GPU_SOURCE

namespace {

namespace scene = SWEEPGEN_GPU_NAMESPACE;

void check_cuda(cudaError_t status, const char* what) {
  if (status == cudaSuccess) return;
  std::fprintf(stderr, "gpu_bench: %s: %s\n", what, cudaGetErrorString(status));
  std::exit(1);
}

// n random states in rows of n values: q within [-pi, pi] (a floating base's rotation a random
// one), every other input within [-1, 1] (a run-time direction need not be a unit vector).
template <class Scalar>
std::vector<Scalar> random_rows(int n, int in_size, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), unit(-1, 1);
  std::vector<Scalar> rows(static_cast<std::size_t>(in_size) * n);
  for (int s = 0; s < n; ++s) {
    const auto at = [&](int k) -> Scalar& { return rows[static_cast<std::size_t>(k) * n + s]; };
    for (int k = 0; k < in_size; ++k) at(k) = static_cast<Scalar>(k < scene::nq ? angle(random) : unit(random));
    if (scene::nq != scene::dof) {  // a floating base: world_R_base from a random unit quaternion
      double w = unit(random), x = unit(random), y = unit(random), z = unit(random);
      const double norm = std::sqrt(w * w + x * x + y * y + z * z);
      w /= norm, x /= norm, y /= norm, z /= norm;
      const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                           2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                           2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
      for (int k = 0; k < 9; ++k) at(k) = static_cast<Scalar>(r[k]);
    }
  }
  return rows;
}

template <class Scalar>
struct Entry {
  const char* name;
  const char* scalar;
  int in_size, out_size;
  cudaError_t (*cuda)(int, const Scalar*, Scalar*, cudaStream_t) noexcept;
  void (*host)(const Scalar*, Scalar*) noexcept;
};

// Milliseconds of `work` on `stream`, the median of 9 runs after one warm-up.
template <class Work>
float median_ms(cudaStream_t stream, Work&& work) {
  cudaEvent_t start, stop;
  check_cuda(cudaEventCreate(&start), "cudaEventCreate");
  check_cuda(cudaEventCreate(&stop), "cudaEventCreate");
  work();
  std::vector<float> ms;
  for (int run = 0; run < 9; ++run) {
    check_cuda(cudaEventRecord(start, stream), "cudaEventRecord");
    work();
    check_cuda(cudaEventRecord(stop, stream), "cudaEventRecord");
    check_cuda(cudaEventSynchronize(stop), "cudaEventSynchronize");
    float elapsed = 0;
    check_cuda(cudaEventElapsedTime(&elapsed, start, stop), "cudaEventElapsedTime");
    ms.push_back(elapsed);
  }
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

// A line per state: its flat input and the GPU's flat output (rows of n values), in hex floats.
template <class Scalar>
void write_sample(std::FILE* file, int states, int n, int in_size, int out_size, const Scalar* in, const Scalar* out) {
  for (int s = 0; s < states; ++s) {
    for (int k = 0; k < in_size; ++k) std::fprintf(file, "%a ", static_cast<double>(in[static_cast<std::size_t>(k) * n + s]));
    for (int k = 0; k < out_size; ++k)
      std::fprintf(file, k + 1 < out_size ? "%a " : "%a\n", static_cast<double>(out[static_cast<std::size_t>(k) * n + s]));
  }
}

// `sample_file`: where the largest n's first `sample` states go (write_sample), or nullptr.
template <class Scalar>
bool run(const Entry<Scalar>& e, const std::vector<int>& sizes, int check, int sample, std::FILE* sample_file) {
  cudaStream_t stream;
  check_cuda(cudaStreamCreate(&stream), "cudaStreamCreate");
  bool ok = true;
  for (const int n : sizes) {
    const std::size_t in_count = static_cast<std::size_t>(e.in_size) * n, out_count = static_cast<std::size_t>(e.out_size) * n;
    const std::vector<Scalar> rows = random_rows<Scalar>(n, e.in_size, 7);
    Scalar *host_in, *host_out, *device_in, *device_out;
    check_cuda(cudaMallocHost(reinterpret_cast<void**>(&host_in), in_count * sizeof(Scalar)), "cudaMallocHost");
    check_cuda(cudaMallocHost(reinterpret_cast<void**>(&host_out), out_count * sizeof(Scalar)), "cudaMallocHost");
    check_cuda(cudaMalloc(reinterpret_cast<void**>(&device_in), in_count * sizeof(Scalar)), "cudaMalloc");
    check_cuda(cudaMalloc(reinterpret_cast<void**>(&device_out), out_count * sizeof(Scalar)), "cudaMalloc");
    std::copy(rows.begin(), rows.end(), host_in);
    check_cuda(cudaMemcpy(device_in, host_in, in_count * sizeof(Scalar), cudaMemcpyHostToDevice), "cudaMemcpy");
    const float kernel_ms = median_ms(stream, [&] { check_cuda(e.cuda(n, device_in, device_out, stream), e.name); });
    const float copies_ms = median_ms(stream, [&] {
      check_cuda(cudaMemcpyAsync(device_in, host_in, in_count * sizeof(Scalar), cudaMemcpyHostToDevice, stream), "copy in");
      check_cuda(e.cuda(n, device_in, device_out, stream), e.name);
      check_cuda(cudaMemcpyAsync(host_out, device_out, out_count * sizeof(Scalar), cudaMemcpyDeviceToHost, stream), "copy out");
    });
    check_cuda(cudaStreamSynchronize(stream), "cudaStreamSynchronize");
    // The GPU against the host on the first `check` states (of the largest n only).
    double worst = 0;
    long status_differs = 0;
    const int checked = n == sizes.back() ? std::min(check, n) : 0;
    std::vector<Scalar> state_in(e.in_size), state_out(e.out_size);
    for (int s = 0; s < checked; ++s) {
      for (int k = 0; k < e.in_size; ++k) state_in[k] = host_in[static_cast<std::size_t>(k) * n + s];
      e.host(state_in.data(), state_out.data());
      for (int k = 0; k + 1 < e.out_size; ++k) {
        const double gpu = host_out[static_cast<std::size_t>(k) * n + s], cpu = state_out[k];
        if (std::isnan(cpu) && std::isnan(gpu)) continue;
        worst = std::max(worst, std::abs(gpu - cpu) / std::max(1.0, std::abs(cpu)));
      }
      status_differs += host_out[static_cast<std::size_t>(e.out_size - 1) * n + s] != state_out[e.out_size - 1];
    }
    std::printf("gpu: %-28s %-4s n %8d  kernel %9.3f ms %10.3g states/s  with copies %9.3f ms %10.3g states/s",
                e.name, e.scalar, n, kernel_ms, n / (kernel_ms * 1e-3), copies_ms, n / (copies_ms * 1e-3));
    if (checked) std::printf("  against the CPU on %d states: max rel. difference %.3g, status differs on %ld", checked, worst, status_differs);
    if (checked && sample_file) write_sample(sample_file, std::min(sample, n), n, e.in_size, e.out_size, host_in, host_out);
    std::printf("\n");
    ok = ok && status_differs == 0;
    cudaFree(device_out);
    cudaFree(device_in);
    cudaFreeHost(host_out);
    cudaFreeHost(host_in);
  }
  cudaStreamDestroy(stream);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: gpu_bench <check states> <sample states> <sample file> <n>...\n");
    return 2;
  }
  const int check = std::atoi(argv[1]), sample = std::atoi(argv[2]);
  std::FILE* sample_file = std::fopen(argv[3], "w");
  if (sample_file == nullptr) {
    std::fprintf(stderr, "gpu_bench: %s: cannot be written\n", argv[3]);
    return 1;
  }
  std::vector<int> sizes;
  for (int i = 4; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
  std::sort(sizes.begin(), sizes.end());
  bool ok = run(Entry<double>{"solve_original", "f64", scene::f64::flat_in_size, scene::f64::flat_out_size,
                              &scene::f64::solve_original_cuda, &scene::f64::solve_original_flat},
                sizes, check, sample, sample_file);
  std::fclose(sample_file);
#if defined(SWEEPGEN_GPU_HAS_DERIVATIVES)
  ok = run(Entry<double>{"derivatives_original", "f64", scene::f64::flat_in_size, scene::f64::derivative_flat_out_size,
                         &scene::f64::derivatives_original_cuda, &scene::f64::derivatives_original_flat},
           sizes, check, 0, nullptr) && ok;
#endif
#if defined(SWEEPGEN_GPU_HAS_F32)
  ok = run(Entry<float>{"solve_original", "f32", scene::f32::flat_in_size, scene::f32::flat_out_size,
                        &scene::f32::solve_original_cuda, &scene::f32::solve_original_flat},
           sizes, check, 0, nullptr) && ok;
#endif
  return ok ? 0 : 1;
}
