/* locus/export.h — which symbols a shared liblocus exports (docs/shipping.md).
 *
 * The library is compiled with hidden visibility (-fvisibility=hidden): its
 * kernels, pipelines, METIS and template instantiations stay private to
 * liblocus.so, so they can neither clash with a host's copies (a host that
 * links Debian's METIS or its own Eigen) nor be mistaken for a stable ABI.
 * What the public headers declare between LOCUS_API_BEGIN and LOCUS_API_END
 * is exported: the locus_* C API of locus.h and the C++ API (Session, Mesh,
 * Error, mesh I/O, CscMatrix helpers). C and C++. */
#ifndef LOCUS_EXPORT_H
#define LOCUS_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define LOCUS_API_BEGIN _Pragma("GCC visibility push(default)")
#define LOCUS_API_END _Pragma("GCC visibility pop")
#else
#define LOCUS_API_BEGIN
#define LOCUS_API_END
#endif

#endif /* LOCUS_EXPORT_H */
