// Kernels compiled twice, for the x86-64 baseline and for an instruction-set extension
// (__attribute__((target("...")))), the copy chosen at run time with __builtin_cpu_supports:
// possible with GCC and Clang on x86-64. Both copies must compute the same values.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RGBDI_HAVE_X86_DISPATCH 1
#endif
