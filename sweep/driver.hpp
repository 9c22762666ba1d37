// The campaign driver: `planetwear sweep` on 1..P MPI ranks.
//
//   rank 0, main thread    setup (campaign, design, validation of every case,
//                          output checks, resume) before any rank computes;
//                          then the master loop: all MPI calls
//                          (MPI_THREAD_FUNNELED), hands out cases one at a
//                          time on request, journals every result, schedules
//                          checkpoints, prints progress. Polls with
//                          MPI_Iprobe and ~1 ms sleeps, so it needs almost no
//                          CPU.
//   rank 0, worker thread  runs cases handed to it through a queue, like any
//                          other rank (so -np 1 uses one core, -np 2 two).
//   rank 0, writer thread  writes checkpoints (the only thread touching HDF5
//                          during the run), while cases keep running.
//   ranks 1..P-1           request a case, run it, send the result back
//                          (serialized CaseRecord), repeat until told to stop.
//
// Crash safety (docs/archive-format.md): the archive is only ever replaced by
// an atomic rename of a complete, fsync'ed temporary file; every finished
// case is first written to "<archive>.journal/" (one file per case, atomic).
// A checkpoint rewrites the archive from memory (archive + journal merged)
// and deletes the merged journal entries; the last one removes the journal.
// --resume reads both and runs only the cases that are neither done nor failed.
//
// Results do not depend on the number of ranks or threads: each case is
// deterministic and is stored at its case index.
#pragma once

#include "io/exit_code.hpp"

#include <cstddef>
#include <filesystem>
#include <iosfwd>

namespace pw::sweep {

struct SweepOptions {
  std::filesystem::path campaign;  ///< campaign TOML file
  std::filesystem::path output;    ///< archive (HDF5)
  bool resume = false;             ///< continue an interrupted archive
  bool force = false;              ///< replace an existing archive
  bool quiet = false;              ///< no progress on stderr
  int checkpoint_cases = 32;       ///< checkpoint after this many finished cases (>= 1)
  double checkpoint_seconds = 60;  ///< ... or this many seconds since the last one (> 0)
  /// Run only cases case_begin <= i < case_end (an array-job slice); the
  /// archive still holds every case, the others pending. case_end is clamped
  /// to the number of cases.
  std::size_t case_begin = 0;
  std::size_t case_end = static_cast<std::size_t>(-1);
};

/// Exit code when the campaign finished but some cases failed (io/exit_code.hpp).
inline constexpr int kExitCasesFailed = static_cast<int>(io::ExitCode::Incomplete);

/// Runs the campaign on every rank of MPI_COMM_WORLD (MPI_Init_thread and
/// MPI_Finalize happen in here). Returns the exit code: on rank 0, 0 if all
/// cases are done and kExitCasesFailed if some failed; 0 on the other ranks
/// (so that mpirun reports rank 0's status and never kills rank 0 early). An
/// error before the run (bad campaign, invalid case, existing output, changed
/// campaign on resume) is rethrown on rank 0 after MPI_Finalize
/// (pw::InputError -> exit 1, pw::io::IoError -> 3, as for every subcommand);
/// nothing is written then. An I/O error during the run
/// aborts all ranks (MPI_Abort, exit 3); the archive keeps its last
/// checkpoint and the journal everything after it. `log` gets progress and
/// the summary (rank 0 only).
int run_sweep(const SweepOptions& options, std::ostream& log);

} // namespace pw::sweep
