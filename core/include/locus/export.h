/* locus/export.h — which symbols a shared liblocus exports (docs/shipping.md).
 *
 * The library is compiled with hidden visibility (-fvisibility=hidden): its
 * kernels, pipelines, METIS and template instantiations stay private to
 * liblocus.so, so they can neither clash with a host's copies (a host that
 * links Debian's METIS or its own Eigen) nor be mistaken for a stable ABI.
 * Every public declaration carries LOCUS_API: each locus_* function of the C
 * API and each class, struct and free function of the C++ API. One macro per
 * declaration, not a region, because that is what MSVC needs (__declspec on
 * the declaration); GCC and Clang use the same marks, so the Linux build and
 * its export checks (tests/package) exercise exactly what Windows would.
 *
 * Windows: building the DLL defines LOCUS_BUILDING (dllexport); a host of the
 * DLL defines nothing (dllimport); a host of the static library, and the
 * static library itself, define LOCUS_STATIC (the CMake targets do both).
 * LOCUS_API_BEGIN/END remain as markers of the API region and expand to
 * nothing. C and C++. */
#ifndef LOCUS_EXPORT_H
#define LOCUS_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(LOCUS_STATIC)
#define LOCUS_API
#elif defined(LOCUS_BUILDING)
#define LOCUS_API __declspec(dllexport)
#else
#define LOCUS_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define LOCUS_API __attribute__((visibility("default")))
#else
#define LOCUS_API
#endif

#define LOCUS_API_BEGIN
#define LOCUS_API_END

#endif /* LOCUS_EXPORT_H */
