// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the one way to build a function in several instruction-set versions.
 *
 * SEMS_TARGET_CLONES("avx2", "default") before a function asks GCC for one version per
 * target and an ifunc resolver that picks one when the library is loaded. The resolver
 * runs while the dynamic loader relocates the library, before any sanitizer runtime is
 * up; compiled with ThreadSanitizer instrumentation it calls into the missing runtime and
 * the process dies before main. So under ThreadSanitizer (and with clang, whose clones
 * this module does not use) the macro is empty: only the "default" version is built, with
 * no resolver, and it is instrumented like any other code. Every version of a cloned
 * function must give the same results (the clone sites say how they keep that), so the
 * sanitized build checks the code that runs in production.
 *
 * Every target_clones in the module goes through this macro: the top-level CMakeLists.txt
 * refuses to configure when a source under lib/, apps/, include/ or python/ spells
 * target_clones, target_version or ifunc anywhere else, and scripts/sanitize_thread.sh
 * refuses a ThreadSanitizer build whose libraries or runner still carry an IFUNC symbol.
 */
#ifndef INCLUDED_SEMS_CORE_CPU_DISPATCH_H
#define INCLUDED_SEMS_CORE_CPU_DISPATCH_H

#if defined(__SANITIZE_THREAD__)
#define SEMS_NO_IFUNC 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SEMS_NO_IFUNC 1
#endif
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(SEMS_NO_IFUNC)
#define SEMS_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#else
#define SEMS_TARGET_CLONES(...)
#endif

#endif // INCLUDED_SEMS_CORE_CPU_DISPATCH_H
