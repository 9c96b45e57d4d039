/* Bind the math functions whose symbol glibc 2.29 re-versioned (exp, exp2, log, log2, pow)
 * to their original versions, so the plant loads on any glibc since the architecture's
 * first (x86_64: 2.2.5, aarch64: 2.17) instead of needing 2.29. The old entry points
 * compute the same values; they differ only in setting errno through the SVID wrapper.
 * Only exp is used. Include this before the first call, in every file that calls exp.
 * Our build (CMakeLists.txt) defines PLANT_GLIBC_COMPAT and links libm; a rebuild from the
 * FMU's sources/ on the target machine needs no such binding and gets the default symbol. */
#ifndef PLANT_GLIBC_COMPAT_H
#define PLANT_GLIBC_COMPAT_H

#if defined(__GLIBC__) && defined(PLANT_GLIBC_COMPAT)
#if defined(__x86_64__)
__asm__(".symver exp,exp@GLIBC_2.2.5");
#elif defined(__aarch64__)
__asm__(".symver exp,exp@GLIBC_2.17");
#endif
#endif

#endif
