#include "core/prefault.hpp"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pw {
namespace {

#if defined(__linux__)
/// MADV_POPULATE_WRITE's value in Linux's uapi (mman-common.h); glibc 2.36's headers lack it.
constexpr int kMadvPopulateWrite = 23;

/// Advises the whole pages inside [p, p + bytes). Failures are ignored on purpose: the advice
/// changes only how fast the pages appear, never their contents (see prefault.hpp).
void advise_pages(void* p, std::size_t bytes) {
  const long page_size = sysconf(_SC_PAGESIZE);
  if (page_size <= 0) return;
  const auto page = static_cast<std::uintptr_t>(page_size);
  const auto begin = (reinterpret_cast<std::uintptr_t>(p) + page - 1) & ~(page - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(page - 1);
  if (end <= begin) return;
  void* const start = reinterpret_cast<void*>(begin);
  const std::size_t length = end - begin;
  (void)madvise(start, length, MADV_HUGEPAGE);
  (void)madvise(start, length, kMadvPopulateWrite);
}
#endif

} // namespace

void resize_prefaulted(std::vector<double>& v, std::size_t n) {
#if defined(__linux__)
  if (v.capacity() < n && n * sizeof(double) >= kPrefaultMinBytes) {
    std::vector<double> fresh;
    fresh.reserve(n);  // storage without a write to it: its pages are not mapped yet
    advise_pages(fresh.data(), n * sizeof(double));
    fresh.assign(v.begin(), v.end());
    v.swap(fresh);
  }
#endif
  v.resize(n);
}

} // namespace pw
