// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: LibTorch's CPU tensors under AddressSanitizer. See asan_tensor_cache.h. */
#include "learning/memory/asan_tensor_cache.h"

#if defined(__SANITIZE_ADDRESS__)
#define SEMS_HAS_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SEMS_HAS_ASAN 1
#endif
#endif

#ifdef SEMS_HAS_ASAN
#include <c10/core/Allocator.h>
#include <c10/core/CPUAllocator.h>
#include <sanitizer/asan_interface.h>
#include <cstdlib>
#include <mutex>
#include <new>
#include <unordered_map>
#include <vector>
#endif

namespace gr {
namespace sems {

#ifdef SEMS_HAS_ASAN
namespace {

constexpr std::size_t min_cached = std::size_t(128) << 10; // ASan's allocator maps blocks above this
constexpr std::size_t alignment = 64;                      // LibTorch's own (c10::gAlignment)

class asan_tensor_cache final : public c10::Allocator
{
public:
    explicit asan_tensor_cache(std::size_t limit) : d_limit(limit) {}

    c10::DataPtr allocate(std::size_t n) const override
    {
        if (n == 0)
            return { nullptr, nullptr, &release, c10::Device(c10::DeviceType::CPU) };
        void* p = nullptr;
        if (n < min_cached) { // ASan's own allocator serves these well
            if (::posix_memalign(&p, alignment, n) != 0)
                throw std::bad_alloc();
            return { p, p, &release, c10::Device(c10::DeviceType::CPU) };
        }
        std::lock_guard<std::mutex> guard(d_lock);
        auto it = d_free.find(n);
        if (it != d_free.end() && !it->second.empty()) {
            p = it->second.back();
            it->second.pop_back();
            d_cached -= n;
            ASAN_UNPOISON_MEMORY_REGION(p, n);
        } else if (::posix_memalign(&p, alignment, n) != 0) {
            throw std::bad_alloc();
        }
        d_size[p] = n;
        return { p, p, &release, c10::Device(c10::DeviceType::CPU) };
    }

    c10::DeleterFnPtr raw_deleter() const override { return &release; }

    static asan_tensor_cache* instance; // never destroyed: tensors may outlive static destruction

private:
    static void release(void* p)
    {
        if (p && instance && instance->keep(p))
            return;
        std::free(p);
    }

    // True when p is now cached (poisoned); false: the caller frees it.
    bool keep(void* p) const
    {
        std::lock_guard<std::mutex> guard(d_lock);
        auto it = d_size.find(p);
        if (it == d_size.end())
            return false; // a small block
        const std::size_t n = it->second;
        d_size.erase(it);
        if (n > d_limit)
            return false;
        if (d_cached + n > d_limit)
            flush(); // sizes of work that is over (an earlier phase or test) make room
        d_free[n].push_back(p);
        d_cached += n;
        ASAN_POISON_MEMORY_REGION(p, n);
        return true;
    }

    // Frees every cached block (called with d_lock held).
    void flush() const
    {
        for (auto& [n, blocks] : d_free)
            for (void* p : blocks) {
                ASAN_UNPOISON_MEMORY_REGION(p, n);
                std::free(p);
            }
        d_free.clear();
        d_cached = 0;
    }

    const std::size_t d_limit;
    mutable std::mutex d_lock;
    mutable std::unordered_map<void*, std::size_t> d_size;               // live large blocks
    mutable std::unordered_map<std::size_t, std::vector<void*>> d_free; // cached, by size
    mutable std::size_t d_cached = 0;
};

asan_tensor_cache* asan_tensor_cache::instance = nullptr;

} // namespace

std::string install_asan_tensor_cache(std::size_t limit)
{
    static const std::string done = [limit] {
        asan_tensor_cache::instance = new asan_tensor_cache(limit); // reachable: not a leak
        // Priority 1: above LibTorch's default CPU allocator (registered at 0).
        c10::SetCPUAllocator(asan_tensor_cache::instance, 1);
        return "AddressSanitizer: tensor blocks >= 128 KiB cached by size, poisoned while cached, up to " +
               std::to_string(limit >> 20) + " MiB";
    }();
    return done;
}
#else
std::string install_asan_tensor_cache(std::size_t) { return ""; }
#endif

} // namespace sems
} // namespace gr
