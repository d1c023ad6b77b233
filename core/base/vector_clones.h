#pragma once
/// SOFTTOUCH_VECTOR_CLONES before a function builds it twice, for AVX2 and for the x86-64 baseline,
/// and picks one when the program loads (GCC function multi-versioning). Only for loops whose
/// vectorised form performs the same IEEE operations in the same order as the scalar one: with FMA
/// contraction off (cmake/SoftTouchOptions.cmake) a clone changes speed, never a result bit.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SOFTTOUCH_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SOFTTOUCH_VECTOR_CLONES
#endif
