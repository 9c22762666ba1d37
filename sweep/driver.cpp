#include "driver.hpp"

#include "archive.hpp"
#include "campaign.hpp"
#include "case_record.hpp"
#include "journal.hpp"
#include "mpi_wait.hpp"

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/config_toml.hpp"
#include "io/exit_code.hpp"
#include "io/io_error.hpp"
#include "model/simulation.hpp"
#include "wear/simulation.hpp"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <iomanip>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>

#include <unistd.h>

namespace pw::sweep {
namespace {

using Clock = std::chrono::steady_clock;
using RecordPtr = std::shared_ptr<const CaseRecord>;

enum Tag : int { kTagReady = 1, kTagJob = 2, kTagResult = 3, kTagStop = 4 };

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// --- messages -----------------------------------------------------------------

/// One case to run: its index and fully resolved configuration (TOML, which
/// round-trips exactly), so workers need no files.
struct Job {
  std::int64_t index = -1;
  std::string config_toml;
  RecordOptions options;
};

std::vector<char> encode(const Job& j) {
  ByteWriter w;
  w.i64(j.index);
  w.str(j.config_toml);
  w.i64(j.options.time_history_decimation);
  w.f64(j.options.spectrum_max_frequency_Hz);
  return w.take();
}

Job decode(std::span<const char> bytes) {
  ByteReader r(bytes);
  Job j;
  j.index = r.i64();
  j.config_toml = r.str();
  j.options.time_history_decimation = static_cast<int>(r.i64());
  j.options.spectrum_max_frequency_Hz = r.f64();
  return j;
}

/// Runs one case; never throws (a failure becomes a failed record).
std::vector<char> run_case(const Job& job, int rank) {
  const auto t0 = Clock::now();
  CaseRecord rec;
  try {
    const model::SimulationConfig config = io::parse_config(job.config_toml, "case " + std::to_string(job.index));
    const model::SimulationResult result = wear::simulate(config);
    rec = make_case_record(result, job.options);
  } catch (const std::exception& e) {
    rec = failed_record(job.index, e.what());
  } catch (...) {
    rec = failed_record(job.index, "unknown error");
  }
  rec.index = job.index;
  rec.rank = rank;
  rec.wall_time_s = seconds_since(t0);
  std::vector<char> bytes = serialize(rec);
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) {
    CaseRecord f = failed_record(job.index, "result record larger than 2 GiB; lower output.time_history_decimation");
    f.rank = rank;
    f.wall_time_s = rec.wall_time_s;
    bytes = serialize(f);
  }
  return bytes;
}

// --- ranks 1..P-1 ---------------------------------------------------------------

void worker_rank(int rank) {
  MPI_Send(nullptr, 0, MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD);
  for (;;) {
    const MPI_Status status = probe_polite(0);
    const std::vector<char> message = receive(status);
    if (status.MPI_TAG == kTagStop) return;
    const std::vector<char> result = run_case(decode(message), rank);
    MPI_Request request;
    MPI_Isend(result.data(), static_cast<int>(result.size()), MPI_CHAR, 0, kTagResult, MPI_COMM_WORLD, &request);
    wait_polite(request);
  }
}

// --- rank 0: worker thread --------------------------------------------------------

/// Runs cases on a thread of rank 0, one at a time, handed over through a
/// mutex-protected slot; results come back serialized, as from other ranks.
class LocalWorker {
public:
  LocalWorker() : thread_([this] { loop(); }) {}
  ~LocalWorker() { stop(); }
  LocalWorker(const LocalWorker&) = delete;
  LocalWorker& operator=(const LocalWorker&) = delete;

  bool idle() const {
    std::lock_guard lock(mutex_);
    return !job_ && !running_;
  }
  void submit(Job job) {
    {
      std::lock_guard lock(mutex_);
      job_ = std::move(job);
    }
    cv_.notify_one();
  }
  std::optional<std::vector<char>> poll() {
    std::lock_guard lock(mutex_);
    if (results_.empty()) return std::nullopt;
    std::vector<char> r = std::move(results_.front());
    results_.pop_front();
    return r;
  }
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

private:
  void loop() {
    for (;;) {
      Job job;
      {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [this] { return job_ || stop_; });
        if (!job_) return;
        job = std::move(*job_);
        job_.reset();
        running_ = true;
      }
      std::vector<char> result = run_case(job, 0);
      std::lock_guard lock(mutex_);
      results_.push_back(std::move(result));
      running_ = false;
    }
  }

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::optional<Job> job_;
  bool running_ = false, stop_ = false;
  std::deque<std::vector<char>> results_;
  std::thread thread_;  // last: starts after the members above exist
};

// --- rank 0: checkpoint writer thread ------------------------------------------------

/// Rewrites the archive from a snapshot of the records: temporary file,
/// fsync, atomic rename (io::AtomicOutput); then deletes the journal entries
/// the snapshot contains.
void write_checkpoint(const std::filesystem::path& output, const Campaign& c, const std::vector<RecordPtr>& records,
                      const ArchiveRunInfo& info) {
  io::AtomicOutput out(output, true);
  write_archive(out.temp_path(), c, records, info);
  out.commit();
}

class CheckpointWriter {
public:
  CheckpointWriter(const std::filesystem::path& output, const Campaign& c, ArchiveRunInfo info)
      : output_(output), campaign_(c), info_(info), thread_([this] { loop(); }) {}
  ~CheckpointWriter() { finish(); }
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  bool busy() const {
    std::lock_guard lock(mutex_);
    return task_.has_value();
  }
  void submit(std::vector<RecordPtr> records, std::vector<std::filesystem::path> merged) {
    {
      std::lock_guard lock(mutex_);
      task_ = Task{std::move(records), std::move(merged)};
    }
    cv_.notify_one();
  }
  /// The error of a failed checkpoint, once.
  std::exception_ptr take_error() {
    std::lock_guard lock(mutex_);
    return std::exchange(error_, nullptr);
  }
  /// Waits for the current task and ends the thread.
  void finish() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  int count() const { return count_; }
  double total_seconds() const { return total_s_; }
  double max_seconds() const { return max_s_; }

private:
  struct Task {
    std::vector<RecordPtr> records;
    std::vector<std::filesystem::path> merged;
  };
  void loop() {
    for (;;) {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [this] { return task_ || stop_; });
      if (!task_) return;
      Task& task = *task_;
      lock.unlock();
      const auto t0 = Clock::now();
      std::exception_ptr error;
      try {
        write_checkpoint(output_, campaign_, task.records, info_);
        Journal::remove(task.merged);
      } catch (...) {
        error = std::current_exception();
      }
      const double s = seconds_since(t0);
      lock.lock();
      ++count_;
      total_s_ += s;
      max_s_ = std::max(max_s_, s);
      if (error) error_ = error;
      task_.reset();
    }
  }

  const std::filesystem::path output_;
  const Campaign& campaign_;
  const ArchiveRunInfo info_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::optional<Task> task_;
  bool stop_ = false;
  std::exception_ptr error_;
  int count_ = 0;
  double total_s_ = 0, max_s_ = 0;
  std::thread thread_;
};

// --- rank 0: setup ---------------------------------------------------------------------

struct Setup {
  Campaign campaign;
  std::vector<RecordPtr> records;  ///< per case; null = to run
  std::unique_ptr<Journal> journal;
  std::size_t case_begin = 0, case_end = 0;  ///< the slice this run computes
};

/// Removes "<output>.partial-<pid>" files left by killed runs.
void remove_stale_partials(const std::filesystem::path& output) {
  const std::filesystem::path dir = output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
  const std::string prefix = output.filename().string() + ".partial-";
  std::error_code ec;
  std::vector<std::filesystem::path> stale;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() > prefix.size() && name.starts_with(prefix) &&
        name.find_first_not_of("0123456789", prefix.size()) == std::string::npos)
      stale.push_back(e.path());
  }
  for (const auto& p : stale) std::filesystem::remove(p, ec);
}

Setup prepare(const SweepOptions& o, int ranks, std::ostream& log) {
  require(!(o.resume && o.force), "--resume", "give --resume or --force, not both");
  require(o.checkpoint_cases >= 1, "--checkpoint-cases", "must be >= 1, got ", o.checkpoint_cases);
  require(o.checkpoint_seconds > 0, "--checkpoint-seconds", "must be > 0, got ", o.checkpoint_seconds);
  Setup s;
  s.campaign = read_campaign(o.campaign);
  const Campaign& c = s.campaign;
  validate_cases(c);
  const std::size_t n = c.cases.size();
  // Array-job slice: cases [begin, end) (end clamped to the case count).
  s.case_begin = o.case_begin;
  s.case_end = std::min(o.case_end, n);
  require(s.case_begin < s.case_end, "--cases",
          detail::concat("empty range ", o.case_begin, ":", o.case_end, " of a campaign with ", n, " cases"));

  const std::filesystem::path& out = o.output;
  const std::filesystem::path dir = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw io::IoError(out.string() + ": output directory '" + dir.string() + "' does not exist");
  if (std::filesystem::is_directory(out, ec)) throw io::IoError(out.string() + ": is a directory, expected a file name");
  const std::filesystem::path jdir = Journal::directory_for(out);
  const bool archive_exists = std::filesystem::exists(out, ec);
  const bool journal_exists = std::filesystem::exists(jdir, ec);
  if ((archive_exists || journal_exists) && !o.resume && !o.force)
    throw InputError("--output", detail::concat(archive_exists ? out.string() : jdir.string(),
                                                " exists; use --resume to continue that campaign or --force to "
                                                "replace it"));

  s.records.assign(n, nullptr);
  if (o.resume && archive_exists) {
    ArchiveContents a = read_archive(out);
    if (a.input_hash != hex64(c.input_hash))
      throw InputError("--resume", detail::concat(out.string(), " was written for other campaign inputs (input hash ",
                                                  a.input_hash, ", now ", hex64(c.input_hash),
                                                  "): the campaign file, its base config or its case list changed. "
                                                  "Refusing to resume; restore them, or start over with --force"));
    if (a.design_hash != hex64(c.design_hash) || a.cases != n)
      throw InputError("--resume", detail::concat(out.string(), " holds a design of ", a.cases, " cases (hash ",
                                                  a.design_hash, ") but the campaign now resolves to ", n,
                                                  " cases (hash ", hex64(c.design_hash),
                                                  "), e.g. after a software update. Refusing to resume"));
    if (a.case_begin != s.case_begin || a.case_end != s.case_end)
      throw InputError("--cases", detail::concat(out.string(), " was written for cases ", a.case_begin, ":",
                                                 a.case_end, ", not ", s.case_begin, ":", s.case_end,
                                                 "; resume with the same --cases range"));
    for (auto& r : a.records) {
      const auto i = static_cast<std::size_t>(r.index);
      s.records[i] = std::make_shared<const CaseRecord>(std::move(r));
    }
  }

  s.journal = std::make_unique<Journal>(jdir, c.input_hash);
  s.journal->lock();
  try {
    if (o.force) s.journal->clear();
    if (o.resume) {
      std::vector<std::string> notes;
      for (auto& e : s.journal->read(notes)) {
        const auto i = static_cast<std::size_t>(e.record.index);
        if (e.record.index < 0 || i >= n) {
          notes.push_back(e.path.string() + ": ignored (case index out of range)");
          continue;
        }
        s.records[i] = std::make_shared<const CaseRecord>(std::move(e.record));
      }
      if (!o.quiet)
        for (const auto& note : notes) log << "planetwear sweep: " << note << "\n";
    }
    if (o.resume || o.force) remove_stale_partials(out);
    // The first checkpoint: a fresh archive with every case pending, or the
    // archive and journal merged. Journal entries are deleted after it.
    write_checkpoint(out, c, s.records, {ranks, s.case_begin, s.case_end});
    s.journal->clear();
  } catch (...) {
    if (!o.resume && !archive_exists && !journal_exists) s.journal->remove_directory();
    throw;
  }
  return s;
}

// --- rank 0: master loop ------------------------------------------------------------------

class Progress {
public:
  Progress(bool quiet, std::ostream& log, std::size_t total)
      : quiet_(quiet), tty_(::isatty(STDERR_FILENO) == 1), log_(log), total_(total), start_(Clock::now()) {}

  void update(std::size_t finished_total, std::size_t failed_total, std::size_t finished_run, std::size_t remaining,
              int running, bool force = false) {
    if (quiet_) return;
    const auto now = Clock::now();
    const auto every = tty_ ? std::chrono::milliseconds(500) : std::chrono::milliseconds(10000);
    if (!force && now - last_ < every) return;
    last_ = now;
    const double elapsed = seconds_since(start_);
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << "[sweep] " << finished_total << "/" << total_ << " cases";
    if (failed_total) s << " (" << failed_total << " failed)";
    s << ", " << running << " running, elapsed " << elapsed << " s, ETA ";
    if (finished_run > 0) s << elapsed / static_cast<double>(finished_run) * static_cast<double>(remaining) << " s";
    else s << "?";
    if (tty_) log_ << "\r" << s.str() << "   " << (force ? "\n" : "") << std::flush;
    else log_ << s.str() << "\n" << std::flush;
  }
  void note(const std::string& line) {
    if (quiet_) return;
    if (tty_) log_ << "\r";
    log_ << line << "\n" << std::flush;
  }

private:
  bool quiet_, tty_;
  std::ostream& log_;
  std::size_t total_;
  Clock::time_point start_, last_{};
};

/// Ends every rank at once (MPI_Abort); the archive keeps its last checkpoint.
[[noreturn]] void abort_run(std::ostream& log, const std::filesystem::path& output, const std::string& what) {
  log << "\n" << io::kErrorPrefix << "sweep: " << what << "\nplanetwear sweep: aborting; " << output.string()
      << " keeps its last checkpoint and the journal the cases finished since; continue with --resume\n"
      << std::flush;
  MPI_Abort(MPI_COMM_WORLD, io::to_int(io::ExitCode::IoFailure));
  std::_Exit(io::to_int(io::ExitCode::IoFailure));
}

/// The cases of this run without a record yet, in order; counts those already finished
/// (and failed) into `finished` and `failed`.
std::deque<std::size_t> pending_cases(const Setup& s, std::size_t& finished, std::size_t& failed) {
  std::deque<std::size_t> pending;
  for (std::size_t i = s.case_begin; i < s.case_end; ++i) {
    if (!s.records[i]) {
      pending.push_back(i);
      continue;
    }
    ++finished;
    if (s.records[i]->status == CaseStatus::Failed) ++failed;
  }
  return pending;
}

/// What the run's summary lines report.
struct RunFigures {
  double wall_s, case_seconds, busy_seconds, final_s;
  std::size_t finished_run, finished_total, failed_total, during_checkpoint, running_at_checkpoints;
};

/// The two summary lines at the end of a run.
std::string run_summary(const SweepOptions& o, const Setup& s, int ranks, const RunFigures& f,
                        const CheckpointWriter& writer) {
  const std::size_t n = s.campaign.cases.size();
  std::ostringstream sum;
  sum << std::fixed << std::setprecision(3) << "planetwear sweep: " << f.finished_run << " cases run in " << f.wall_s
      << " s on " << ranks << " rank" << (ranks > 1 ? "s" : "") << " (case time " << f.case_seconds
      << " s); rank-0 driver busy " << f.busy_seconds << " s (MPI + journal), " << writer.count()
      << " checkpoints in " << writer.total_seconds() << " s on the writer thread (max " << writer.max_seconds()
      << " s), final archive " << f.final_s << " s; while checkpoints were written " << f.running_at_checkpoints
      << " case runs were in progress and " << f.during_checkpoint << " finished\n";
  sum << "planetwear sweep: " << o.output.string() << ": " << f.finished_total - f.failed_total << " done, "
      << f.failed_total << " failed of " << s.case_end - s.case_begin;
  if (s.case_end - s.case_begin != n) sum << " (cases " << s.case_begin << ":" << s.case_end << " of " << n << ")";
  sum << "\n";
  return sum.str();
}

int master(const SweepOptions& o, Setup& s, int ranks, std::ostream& log) {
  const Campaign& c = s.campaign;
  const std::size_t n = c.cases.size();
  std::vector<RecordPtr>& records = s.records;
  std::size_t finished_total = 0, failed_total = 0;
  std::deque<std::size_t> pending = pending_cases(s, finished_total, failed_total);
  const auto t_start = Clock::now();
  Progress progress(o.quiet, log, s.case_end - s.case_begin);
  if (!o.quiet)
    log << "planetwear sweep: " << n << " cases, " << pending.size() << " to run on " << ranks << " rank"
        << (ranks > 1 ? "s" : "") << " -> " << o.output.string() << "\n";
  if (!o.quiet)
    for (const std::string& line : rank_correlation_report(c)) log << "planetwear sweep: " << line << "\n";

  LocalWorker local;
  CheckpointWriter writer(o.output, c, {ranks, s.case_begin, s.case_end});
  std::vector<std::filesystem::path> unmerged;  // journal entries since the last checkpoint
  auto last_checkpoint = Clock::now();
  std::size_t since_checkpoint = 0, finished_run = 0, during_checkpoint = 0, running_at_checkpoints = 0;
  double case_seconds = 0, busy_seconds = 0, final_s = 0;
  int outstanding = 0, stopped = 0;
  std::vector<std::int64_t> assigned(static_cast<std::size_t>(ranks), -1);
  struct Send {
    std::vector<char> bytes;
    MPI_Request request;
  };
  std::list<Send> sends;

  auto next_job = [&]() -> Job {
    const std::size_t i = pending.front();
    pending.pop_front();
    return Job{static_cast<std::int64_t>(i), io::to_toml(case_config(c, i)),
               {c.output.time_history_decimation, c.output.spectrum_max_frequency_Hz}};
  };
  auto send = [&](int rank, int tag, std::vector<char> bytes) {
    sends.push_back({std::move(bytes), MPI_REQUEST_NULL});
    Send& m = sends.back();
    MPI_Isend(m.bytes.data(), static_cast<int>(m.bytes.size()), MPI_CHAR, rank, tag, MPI_COMM_WORLD, &m.request);
  };
  auto dispatch = [&](int rank) {  // a rank asks for work
    if (!pending.empty()) {
      Job job = next_job();
      assigned[static_cast<std::size_t>(rank)] = job.index;
      ++outstanding;
      send(rank, kTagJob, encode(job));
    } else {
      send(rank, kTagStop, {});
      ++stopped;
    }
  };
  auto handle = [&](const std::vector<char>& bytes, int rank) {
    CaseRecord rec = deserialize(bytes);
    const auto i = static_cast<std::size_t>(rec.index);
    if (rec.index != assigned[static_cast<std::size_t>(rank)] || rec.index < 0 || i >= n || records[i])
      throw std::logic_error(detail::concat("rank ", rank, " returned case ", rec.index, ", expected ",
                                            assigned[static_cast<std::size_t>(rank)]));
    assigned[static_cast<std::size_t>(rank)] = -1;
    --outstanding;
    unmerged.push_back(s.journal->append(rec.index, bytes));
    ++finished_total, ++finished_run, ++since_checkpoint;
    if (writer.busy()) ++during_checkpoint;
    case_seconds += rec.wall_time_s;
    if (rec.status == CaseStatus::Failed) {
      ++failed_total;
      progress.note(detail::concat("planetwear sweep: case ", rec.index, " (", describe_case(c, i),
                                   ") failed: ", rec.message));
    }
    records[i] = std::make_shared<const CaseRecord>(std::move(rec));
  };

  try {
    while (outstanding > 0 || !pending.empty() || stopped < ranks - 1) {
      const auto t0 = Clock::now();
      bool active = false;
      // Rank 0's own worker thread.
      if (assigned[0] < 0 && !pending.empty() && local.idle()) {
        Job job = next_job();
        assigned[0] = job.index;
        ++outstanding;
        local.submit(std::move(job));
        active = true;
      }
      while (auto bytes = local.poll()) {
        handle(*bytes, 0);
        active = true;
      }
      // Other ranks: requests and results; answer first, then journal.
      for (;;) {
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (!flag) break;
        active = true;
        const std::vector<char> message = receive(status);
        if (status.MPI_TAG == kTagResult) handle(message, status.MPI_SOURCE);
        dispatch(status.MPI_SOURCE);
      }
      for (auto it = sends.begin(); it != sends.end();) {
        int done = 0;
        MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
        it = done ? sends.erase(it) : std::next(it);
      }
      // Checkpoints run on the writer thread while cases continue.
      if (auto error = writer.take_error()) std::rethrow_exception(error);
      if (since_checkpoint > 0 && !writer.busy() &&
          (since_checkpoint >= static_cast<std::size_t>(o.checkpoint_cases) ||
           seconds_since(last_checkpoint) >= o.checkpoint_seconds) &&
          (outstanding > 0 || !pending.empty())) {
        writer.submit(records, std::exchange(unmerged, {}));
        running_at_checkpoints += static_cast<std::size_t>(outstanding);
        since_checkpoint = 0;
        last_checkpoint = Clock::now();
        active = true;
      }
      progress.update(finished_total, failed_total, finished_run, pending.size() + static_cast<std::size_t>(outstanding),
                      outstanding);
      if (active) busy_seconds += seconds_since(t0);
      else std::this_thread::sleep_for(kPollInterval);
    }
    for (auto& m : sends) wait_polite(m.request);
    local.stop();
    writer.finish();
    if (auto error = writer.take_error()) std::rethrow_exception(error);

    // Final checkpoint: everything merged, journal removed.
    const auto t_final = Clock::now();
    write_checkpoint(o.output, c, records, {ranks, s.case_begin, s.case_end});
    s.journal->clear();
    s.journal->remove_directory();
    final_s = seconds_since(t_final);
  } catch (const std::exception& e) {
    // No unwinding: the worker thread may be in the middle of a case.
    abort_run(log, o.output, e.what());
  }
  progress.update(finished_total, failed_total, finished_run, 0, 0, true);
  if (!o.quiet)
    log << run_summary(o, s, ranks,
                       {seconds_since(t_start), case_seconds, busy_seconds, final_s, finished_run, finished_total,
                        failed_total, during_checkpoint, running_at_checkpoints},
                       writer)
        << std::flush;
  return failed_total > 0 ? kExitCasesFailed : 0;
}

} // namespace

int run_sweep(const SweepOptions& o, std::ostream& log) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);

  // Setup on rank 0 while the others wait; nothing runs unless it succeeds.
  std::exception_ptr setup_error;
  std::optional<Setup> setup;
  int code = 0;
  if (rank == 0) {
    try {
      if (provided < MPI_THREAD_FUNNELED)
        throw io::IoError("the MPI library does not support MPI_THREAD_FUNNELED, needed by the sweep driver");
      setup.emplace(prepare(o, ranks, log));
    } catch (...) {
      setup_error = std::current_exception();
      code = io::to_int(io::exit_code_of(setup_error));
    }
  }
  MPI_Request request;
  MPI_Ibcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
  wait_polite(request);
  if (code != 0) {
    setup.reset();
    MPI_Finalize();
    if (setup_error) std::rethrow_exception(setup_error);
    // Only rank 0 reports: a non-zero exit of another rank could make mpirun
    // kill rank 0 before its message is out.
    return 0;
  }

  int result = 0;
  if (rank == 0) {
    result = master(o, *setup, ranks, log);
  } else {
    worker_rank(rank);
  }
  MPI_Request done_request;
  MPI_Ibcast(&result, 1, MPI_INT, 0, MPI_COMM_WORLD, &done_request);
  wait_polite(done_request);
  setup.reset();
  MPI_Finalize();
  return rank == 0 ? result : 0;
}

} // namespace pw::sweep
