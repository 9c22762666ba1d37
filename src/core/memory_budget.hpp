// How much memory one planetwear process may plan to use, and the check that
// refuses an input before the allocation instead of aborting in bad_alloc.
//
// The limit is taken from the machine, not hard-coded: half of the physical
// memory (sysconf(_SC_PHYS_PAGES) x sysconf(_SC_PAGE_SIZE)), lowered to
// RLIMIT_AS when the process has one. The environment variable
// PLANETWEAR_MEMORY_LIMIT overrides it: bytes, or a number with the binary
// suffix K, M, G or T ("512M", "1.5G"). The limit is per process: an MPI
// campaign with P ranks on one node may use P times it (docs/cli.md).
#pragma once

#include <cstdint>
#include <string>

namespace pw {

/// Name of the environment variable that overrides the memory limit.
inline constexpr const char* kMemoryLimitVariable = "PLANETWEAR_MEMORY_LIMIT";

/// The limit in bytes (see the file comment); throws InputError naming
/// PLANETWEAR_MEMORY_LIMIT if its value is not a positive size.
std::uint64_t memory_limit_bytes();

/// Parses a size: "1048576", "512M", "1.5G" (binary suffixes K, M, G, T,
/// optional trailing "B" or "iB"). Throws InputError naming `param`.
std::uint64_t parse_byte_size(const std::string& text, const std::string& param);

/// "1.50 GiB", for messages.
std::string format_bytes(double bytes);

/// Throws InputError naming `param` when `bytes` (an estimate, in double so
/// that it cannot overflow) exceeds memory_limit_bytes(). The message states
/// what needs the memory, the estimate, the limit and its source, and
/// `remedy` (which key or flag to change).
void require_memory(double bytes, const std::string& param, const std::string& what, const std::string& remedy);

} // namespace pw
