// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: glibc's allocator set up for tensor work (private to the learning library). */
#ifndef INCLUDED_SEMS_LEARNING_MALLOC_TUNING_H
#define INCLUDED_SEMS_LEARNING_MALLOC_TUNING_H

#include <string>

namespace gr {
namespace sems {

/*!
 * \brief Once per process: let glibc keep freed tensor memory for reuse.
 *
 * LibTorch on the CPU allocates every intermediate tensor with malloc and frees it at once.
 * With glibc's defaults, blocks above the (dynamic) mmap threshold are mmapped and unmapped
 * per call, and freed memory at the top of a heap is given back to the system when it
 * exceeds the trim threshold; the next call then page-faults it in again. Measured on this
 * project's decoders and trainer (docs/PERFORMANCE.md, "The allocator"): the page faults
 * made inference 3-28x and training 2.4-3.7x slower. Raising both thresholds (mmap at
 * 32 MiB, glibc's maximum; trim at 1 GiB) and the top pad (64 MiB: a block thread's arena
 * keeps an emptied heap instead of unmapping it) keeps the working set in the heap:
 * resident memory stays at the peak working set instead of being returned between calls.
 * Tensors above 32 MiB (a batch of large frames: 256 frames of 14 x 4 096 complex values
 * are 117 MB) would still be mapped per call, so mmap is switched off for the heap
 * (M_MMAP_MAX 0; a block thread's arena still maps what exceeds its 64 MiB heaps).
 * Fast bins are switched off (M_MXFAST 0): with large blocks freed into the heap, glibc
 * consolidated them on every such free, which halved small decoders' batch-1 speed.
 *
 * In a build with AddressSanitizer it installs asan_tensor_cache.h's allocator instead.
 *
 * Called by bundle_decoder and the trainer. It changes nothing if the user already set one
 * of these three (GLIBC_TUNABLES with glibc.malloc.mmap_threshold, .trim_threshold or
 * .top_pad; MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_, MALLOC_TOP_PAD_), with
 * SEMS_MALLOC_TUNING=0, or with a C library other than glibc.
 *
 * \return what was done, for logs: "mmap threshold 32 MiB and no mmap in the heap, trim
 *         threshold 1 GiB, top pad 64 MiB, no fast bins" or why not.
 */
std::string tune_malloc_for_tensors();

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_MALLOC_TUNING_H */
