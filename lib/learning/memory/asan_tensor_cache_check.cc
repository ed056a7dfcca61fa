// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: AddressSanitizer still sees a tensor's memory after the tensor is gone, although
 * asan_tensor_cache.h keeps the block for reuse. Sanitized builds only: CTest expects this
 * program to be stopped by a use-after-poison report; exit 0 means the cache hid the bug. */
#include "learning/memory/asan_tensor_cache.h"
#include <ATen/ops/ones.h> // ATen alone: the same CPU allocator as torch::, a quarter of the compile
#include <cstdio>

int main()
{
    const std::string state = gr::sems::install_asan_tensor_cache();
    std::printf("%s\n", state.c_str());
    volatile float* stale = nullptr;
    {
        auto t = at::ones({ 1 << 16 }); // 256 KiB: a cached size
        stale = t.data_ptr<float>();
    } // freed: now in the cache, poisoned
    std::printf("read after free: %f\n", static_cast<double>(stale[100]));
    return 0;
}
