// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: LibTorch's CPU tensors under AddressSanitizer (private to the learning library). */
#ifndef INCLUDED_SEMS_LEARNING_ASAN_TENSOR_CACHE_H
#define INCLUDED_SEMS_LEARNING_ASAN_TENSOR_CACHE_H

#include <cstddef>
#include <string>

namespace gr {
namespace sems {

/*!
 * \brief In a build with AddressSanitizer: LibTorch's CPU allocator replaced by one that
 * keeps freed tensor blocks of at least 128 KiB for reuse by a request of the same size.
 *
 * Why: AddressSanitizer's allocator maps every block above 128 KiB on its own and unmaps it
 * when it leaves the quarantine, and LibTorch frees every intermediate tensor at once, so a
 * training step or a batched decoder call page-faults its whole working set in again (the
 * sanitized suite spent more system than user CPU time). glibc's equivalent fix
 * (malloc_tuning.h) does not apply: AddressSanitizer replaces glibc's malloc.
 *
 * What AddressSanitizer still sees: a cached block is poisoned until it is handed out again
 * (a use after free of a tensor's memory is still reported, as a use-after-poison), and a
 * block is handed out at exactly its requested size (overflows still reported). The cache
 * holds at most `limit` bytes: a block that would pass it empties the cache first (the sizes
 * of work that is over make room for the current work's).
 *
 * \return what was done, for logs; "" in a build without AddressSanitizer (nothing done).
 */
std::string install_asan_tensor_cache(std::size_t limit = std::size_t(1) << 30);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_ASAN_TENSOR_CACHE_H */
