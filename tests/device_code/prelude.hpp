// What CUDA's headers give device code, for checking generated CUDA sources with clang alone
// (no CUDA SDK: clang++ -x cuda -nocudainc; tests/device_code/check.sh): the execution-space
// attributes, __CUDACC__ (which nvcc defines and clang's CUDA wrapper headers define), the thread
// indices, the math functions' device declarations (clang's own header), and memcpy, which CUDA
// provides on the device and which clang without the SDK takes as host-only.
#define __CUDACC__ 1
#define __host__ __attribute__((host))
#define __device__ __attribute__((device))
#define __global__ __attribute__((global))
#include <cstddef>
__device__ void* memcpy(void* to, const void* from, std::size_t bytes);
#include <__clang_cuda_builtin_vars.h>
#include <__clang_cuda_math_forward_declares.h>
