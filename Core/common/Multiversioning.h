#pragma once
// Functions marked HAIR_AVX2_CLONES are compiled twice, for AVX2 and for the baseline x86-64,
// and picked at load time by the CPU (GCC function multi-versioning): the same operations in
// the same order (no FMA contraction in ISO C++ mode), so the same results bit for bit, with
// 4-wide instead of 2-wide vectors where the CPU has them. Used on loops over long arrays
// (the LU, the stacked products, C's row pass, the finite check, C's per-sample sums: −17 k
// instructions per step at N = 10 for smooth hair, C at N = 40 −16 %); whole assembly
// functions compiled so run no faster.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define HAIR_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define HAIR_AVX2_CLONES
#endif
