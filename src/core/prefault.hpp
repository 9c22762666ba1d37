// Large result buffers with their pages mapped in one request instead of one page fault per
// 4 KiB page.
//
// Why: a simulation that stores every channel at every step writes ~370 bytes of fresh memory
// per step. On the virtual machines this project is measured on, a first touch of an
// anonymous page costs ~10 us (perf: `exc_page_fault` under the vectors' zero fill was 20 % of
// `planetwear simulate`'s profile, session 42), i.e. more than the time step itself. Asking
// for transparent huge pages (madvise MADV_HUGEPAGE: the kernel's default mode "madvise"
// gives them only to regions that ask) and populating the range writable (MADV_POPULATE_WRITE,
// Linux 5.14) maps it in a few calls. Both are advice: a kernel that refuses either leaves the
// vector exactly as resize() makes it, zero-filled, only slower to fill.
#pragma once

#include <cstddef>
#include <vector>

namespace pw {

/// Below this size a buffer is resized plainly: the two system calls cost more than the faults
/// of a few pages save [bytes].
inline constexpr std::size_t kPrefaultMinBytes = std::size_t{1} << 20;

/// v.resize(n) (n zeros for an empty v), with the pages of the new storage requested at once
/// (see the file comment). The values are the same as resize()'s.
void resize_prefaulted(std::vector<double>& v, std::size_t n);

} // namespace pw
