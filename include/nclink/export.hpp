// NCLINK_API marks what libnclink.so exports: the SDK's public classes and
// functions. Everything else is built with hidden visibility (and a version
// script trims what templates leak), so `nm -D libnclink.so` lists the API
// and nothing of the internals, which can change without breaking programs.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define NCLINK_API __attribute__((visibility("default")))
/// For the private insides of an exported class (its Impl): never exported.
#define NCLINK_LOCAL __attribute__((visibility("hidden")))
#else
#define NCLINK_API
#define NCLINK_LOCAL
#endif
