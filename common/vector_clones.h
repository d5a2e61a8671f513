#ifndef PLM_VECTOR_CLONES_H
#define PLM_VECTOR_CLONES_H

/* PLM_VECTOR_CLONES before a hot function's definition compiles it twice,
 * for x86-64-v3 (AVX2 and FMA: 8 floats a vector) and for the build's
 * default target, and the clone the CPU can run is picked once, at load
 * time (GCC's and clang's function multiversioning through glibc's ifunc),
 * so one source serves both and the binary stays portable. A call from a
 * clone to another function pays a call and runs that function's default
 * code (GCC will not inline across targets), unless the callee is declared
 * PLM_VECTOR_INLINE: then it is inlined into each clone and compiled for
 * it. Elsewhere (another architecture or C library) both are plain C.
 * clang (14) gives a clone set's resolver an external name even for a
 * static function, so cloned functions need names unique in the program.
 * PLM_NO_VECTOR_CLONES (the sanitizer build defines it) keeps the default
 * code alone, so that the code CPUs without AVX2 run is tested as well. */
#include <limits.h> /* through the C library's headers: __GLIBC__ */

#if !defined(PLM_NO_VECTOR_CLONES) && defined(__x86_64__) && defined(__GLIBC__) && (defined(__GNUC__) || defined(__clang__))
#define PLM_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#define PLM_VECTOR_INLINE inline __attribute__((always_inline))
#else
#define PLM_VECTOR_CLONES
#define PLM_VECTOR_INLINE inline
#endif

#endif
