// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: glibc's allocator set up for tensor work. See malloc_tuning.h. */
#include "malloc_tuning.h"
#include "learning/memory/asan_tensor_cache.h"
#include <cstdlib>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gr {
namespace sems {

namespace {
std::string apply()
{
    const char* off = std::getenv("SEMS_MALLOC_TUNING");
    if (off && std::strcmp(off, "0") == 0)
        return "not tuned: SEMS_MALLOC_TUNING=0";
    // Under AddressSanitizer glibc's malloc is replaced (mallopt does nothing): the same
    // problem is solved in front of LibTorch instead.
    if (const std::string asan = install_asan_tensor_cache(); !asan.empty())
        return asan;
#if defined(__GLIBC__)
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    for (const char* name :
         { "glibc.malloc.mmap_threshold", "glibc.malloc.mmap_max", "glibc.malloc.trim_threshold", "glibc.malloc.top_pad" })
        if (tunables && std::strstr(tunables, name))
            return std::string("not tuned: GLIBC_TUNABLES sets ") + name;
    if (std::getenv("MALLOC_MMAP_THRESHOLD_") || std::getenv("MALLOC_MMAP_MAX_") || std::getenv("MALLOC_TRIM_THRESHOLD_") ||
        std::getenv("MALLOC_TOP_PAD_"))
        return "not tuned: the environment sets glibc's malloc thresholds (MALLOC_*_)";
    // Setting either threshold disables glibc's dynamic threshold, so both are set. The top
    // pad matters in the block threads: their arenas grow in 64 MiB heaps, and a heap left
    // empty is unmapped whatever the trim threshold, unless the pad asks to keep it.
    //
    // Tensors above glibc's largest mmap threshold (32 MiB) were still mapped and unmapped per
    // call: a batch of 256 NR-sized frames (14 x 4 096 complex values) is 117 MB a tensor, and
    // training at that size spent half its CPU time in the kernel zeroing fresh pages. With
    // no mmap for the heap (M_MMAP_MAX 0) they come from the heap too, and the trim threshold
    // is above such a batch's working set so the heap's top is not given back between batches
    // (an NR-sized decoder epoch went from 3.8 s to 1.1 s). A block thread's arena still maps
    // a request larger than its 64 MiB heaps: glibc falls back to mmap there.
    constexpr int mmap_threshold = 32 << 20; // glibc's upper limit on 64-bit systems
    constexpr int trim_threshold = 1 << 30;
    constexpr int top_pad = 64 << 20;
    if (::mallopt(M_MMAP_THRESHOLD, mmap_threshold) != 1 || ::mallopt(M_TRIM_THRESHOLD, trim_threshold) != 1 ||
        ::mallopt(M_TOP_PAD, top_pad) != 1 || ::mallopt(M_MMAP_MAX, 0) != 1)
        return "not tuned: mallopt refused the thresholds";
    // With tensors up to 32 MiB now freed into the heap, every free of a block >= 64 KiB
    // consolidated the fast bins first: the small classifier's batch-1 call (~30 operators)
    // lost half its speed to it. Without fast bins (the per-thread tcache still serves small
    // blocks) it runs as fast as with glibc's defaults; nothing else moved.
    ::mallopt(M_MXFAST, 0);
    return "mmap threshold 32 MiB and no mmap in the heap, trim threshold 1 GiB, top pad 64 MiB, no fast bins";
#else
    return "not tuned: not glibc";
#endif
}
} // namespace

std::string tune_malloc_for_tensors()
{
    static const std::string done = apply(); // once per process, thread-safe
    return done;
}

} // namespace sems
} // namespace gr
