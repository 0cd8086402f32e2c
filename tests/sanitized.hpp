// Whether this test binary is instrumented by a sanitizer (CI builds them with
// clang, the Release stage with gcc): gcc defines __SANITIZE_ADDRESS__ and
// __SANITIZE_THREAD__, clang answers __has_feature instead.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LOCUS_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define LOCUS_TEST_SANITIZED 1
#endif
#endif
#ifndef LOCUS_TEST_SANITIZED
#define LOCUS_TEST_SANITIZED 0
#endif
