// Polite MPI waiting for the campaign driver and the diagnosis pool: ranks may
// share cores with compute threads (a 2-core laptop), so nothing spins; every
// wait polls with ~1 ms sleeps.
#pragma once

#include <mpi.h>

#include <chrono>
#include <vector>

namespace pw::sweep {

inline constexpr auto kPollInterval = std::chrono::milliseconds(1);

/// Waits for `request` to complete.
void wait_polite(MPI_Request& request);
/// Waits for a message from `source` (MPI_ANY_SOURCE allowed) with any tag.
MPI_Status probe_polite(int source);
/// Receives the probed message (MPI_CHAR) as bytes.
std::vector<char> receive(const MPI_Status& status);

} // namespace pw::sweep
