#include "simulation_pool.hpp"

#include "case_record.hpp"  // ByteWriter, ByteReader
#include "mpi_wait.hpp"

#include "core/error.hpp"
#include "io/config_toml.hpp"
#include "io/exit_code.hpp"
#include "io/io_error.hpp"

#include <atomic>
#include <cstdio>
#include <deque>
#include <exception>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace pw::sweep {
namespace {

// Ready / Unavailable: a serving rank's set-up finished (or failed) -- exactly one of
// them per serving rank. Request: rank 0 -> server, Reply: back. Stop: rank 0 is done.
enum Tag : int { kTagReady = 11, kTagUnavailable = 12, kTagRequest = 13, kTagReply = 14, kTagStop = 15 };
// Reply status: the spectra, or the error class the simulation threw (rethrown as such on rank 0).
enum Status : std::uint32_t { kOk = 0, kInputError = 1, kSolverError = 2, kOtherError = 3 };

void write_matrix(ByteWriter& w, const std::vector<std::vector<double>>& m) {
  w.u32(static_cast<std::uint32_t>(m.size()));
  for (const auto& row : m) w.f64s(row);
}

std::vector<std::vector<double>> read_matrix(ByteReader& r) {
  std::vector<std::vector<double>> m(r.u32());
  for (auto& row : m) row = r.f64s();
  return m;
}

std::vector<char> encode_request(const model::SimulationConfig& config, bool keep) {
  ByteWriter w;
  w.str(io::to_toml(config));
  w.u32(keep ? 1 : 0);
  return w.take();
}

/// Serves one request; never throws (an error travels back with its class).
std::vector<char> serve(const Evaluate& evaluate, std::span<const char> request) {
  ByteWriter w;
  try {
    ByteReader r(request);
    const std::string toml = r.str();
    const bool keep = r.u32() != 0;
    const diagnose::ModelSpectra s = evaluate(io::parse_config(toml, "diagnosis simulation"), keep);
    w.u32(kOk);
    const std::vector<char> bytes = encode_spectra(s);
    w.str(std::string_view(bytes.data(), bytes.size()));
    return w.take();
  } catch (const InputError& e) {
    w.u32(kInputError);
    w.str(e.what());
  } catch (const SolverError& e) {
    w.u32(kSolverError);
    w.str(e.what());
  } catch (const std::exception& e) {
    w.u32(kOtherError);
    w.str(e.what());
  } catch (...) {
    w.u32(kOtherError);
    w.str("unknown error");
  }
  return w.take();
}

/// The reply as spectra, or the simulation's error rethrown as its own class.
diagnose::ModelSpectra open_reply(std::span<const char> reply) {
  ByteReader r(reply);
  const std::uint32_t status = r.u32();
  const std::string payload = r.str();
  switch (status) {
  case kOk: return decode_spectra(std::span<const char>(payload.data(), payload.size()));
  case kInputError: throw InputError("", payload);
  case kSolverError: throw SolverError(payload);
  default: throw std::runtime_error(payload);
  }
}

void serving_rank(const std::function<Evaluate()>& make_evaluate) {
  Evaluate evaluate;
  try {
    evaluate = make_evaluate();
  } catch (...) {
    evaluate = nullptr;  // rank 0 reads the same inputs and reports the error itself
  }
  MPI_Send(nullptr, 0, MPI_CHAR, 0, evaluate ? kTagReady : kTagUnavailable, MPI_COMM_WORLD);
  for (;;) {
    const MPI_Status status = probe_polite(0);
    const std::vector<char> message = receive(status);
    if (status.MPI_TAG == kTagStop) return;
    const std::vector<char> reply = serve(evaluate, message);
    MPI_Request request;
    MPI_Isend(reply.data(), static_cast<int>(reply.size()), MPI_CHAR, 0, kTagReply, MPI_COMM_WORLD, &request);
    wait_polite(request);
  }
}

/// Rank 0's side: the diagnosis's threads hand requests over (remote), the main thread
/// moves them (pump). Idle ranks are those that reported ready and hold no request.
class Pool {
public:
  explicit Pool(int ranks) : ranks_(ranks), reported_(static_cast<std::size_t>(ranks), false) {}

  std::optional<diagnose::ModelSpectra> remote(const model::SimulationConfig& config, bool keep) {
    auto p = std::make_shared<Pending>();
    {
      std::lock_guard lock(mutex_);
      if (idle_.empty()) return std::nullopt;
      p->rank = idle_.back();
      idle_.pop_back();
      p->request = encode_request(config, keep);
      outgoing_.push_back(p);
    }
    const std::vector<char> reply = p->reply.get_future().get();
    return open_reply(reply);
  }

  /// Moves messages until `done` and nothing is in flight.
  void pump(const std::atomic<bool>& done) {
    for (;;) {
      bool worked = false;
      std::deque<std::shared_ptr<Pending>> out;
      {
        std::lock_guard lock(mutex_);
        out.swap(outgoing_);
      }
      for (auto& p : out) {
        MPI_Request request;
        MPI_Isend(p->request.data(), static_cast<int>(p->request.size()), MPI_CHAR, p->rank, kTagRequest,
                  MPI_COMM_WORLD, &request);
        wait_polite(request);
        in_flight_[p->rank] = std::move(p);
        worked = true;
      }
      int flag = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
      if (flag) {
        handle(status);
        worked = true;
      }
      if (done.load() && in_flight_.empty()) {
        std::lock_guard lock(mutex_);
        if (outgoing_.empty()) return;
      }
      if (!worked) std::this_thread::sleep_for(kPollInterval);
    }
  }

  /// After the diagnosis: every serving rank's set-up report is received (none stays
  /// unmatched at MPI_Finalize), then it is told to stop.
  void stop_all() {
    for (int r = 1; r < ranks_; ++r) {
      while (!reported_[static_cast<std::size_t>(r)]) handle(probe_polite(r));
      MPI_Send(nullptr, 0, MPI_CHAR, r, kTagStop, MPI_COMM_WORLD);
    }
  }

private:
  struct Pending {
    int rank = 0;
    std::vector<char> request;
    std::promise<std::vector<char>> reply;
  };

  void handle(const MPI_Status& status) {
    std::vector<char> bytes = receive(status);
    const int r = status.MPI_SOURCE;
    switch (status.MPI_TAG) {
    case kTagReady: {
      reported_[static_cast<std::size_t>(r)] = true;
      std::lock_guard lock(mutex_);
      idle_.push_back(r);
      break;
    }
    case kTagUnavailable: reported_[static_cast<std::size_t>(r)] = true; break;
    case kTagReply: {
      auto it = in_flight_.find(r);
      if (it == in_flight_.end()) throw std::logic_error("simulation pool: reply from a rank with no request");
      std::shared_ptr<Pending> p = std::move(it->second);
      in_flight_.erase(it);
      {
        std::lock_guard lock(mutex_);
        idle_.push_back(r);
      }
      p->reply.set_value(std::move(bytes));
      break;
    }
    default: throw std::logic_error("simulation pool: unexpected message tag " + std::to_string(status.MPI_TAG));
    }
  }

  const int ranks_;
  std::vector<bool> reported_;                           // main thread only
  std::map<int, std::shared_ptr<Pending>> in_flight_;    // main thread only
  std::mutex mutex_;                                     // guards idle_ and outgoing_
  std::vector<int> idle_;
  std::deque<std::shared_ptr<Pending>> outgoing_;
};

} // namespace

std::vector<char> encode_spectra(const diagnose::ModelSpectra& s) {
  ByteWriter w;
  write_matrix(w, s.amplitude);
  w.f64(s.mean_input_rpm);
  w.f64(s.time_step_s);
  w.i64(s.steps_per_mesh);
  w.i64(s.warmup_mesh_cycles);
  write_matrix(w, s.ring_force);
  w.f64s(s.carrier_angle);
  w.f64s(s.planet_angles_rad);
  w.f64s(s.angle_theta);
  write_matrix(w, s.leak_variance);
  w.f64(s.ring_pressure_angle_rad);
  w.f64s(s.ring_acceleration_x);
  w.f64s(s.ring_acceleration_y);
  w.f64(s.ring_mass_kg);
  return w.take();
}

diagnose::ModelSpectra decode_spectra(std::span<const char> bytes) {
  ByteReader r(bytes);
  diagnose::ModelSpectra s;
  s.amplitude = read_matrix(r);
  s.mean_input_rpm = r.f64();
  s.time_step_s = r.f64();
  s.steps_per_mesh = static_cast<int>(r.i64());
  s.warmup_mesh_cycles = static_cast<int>(r.i64());
  s.ring_force = read_matrix(r);
  s.carrier_angle = r.f64s();
  s.planet_angles_rad = r.f64s();
  s.angle_theta = r.f64s();
  s.leak_variance = read_matrix(r);
  s.ring_pressure_angle_rad = r.f64();
  s.ring_acceleration_x = r.f64s();
  s.ring_acceleration_y = r.f64s();
  s.ring_mass_kg = r.f64();
  return s;
}

int run_with_simulation_pool(const std::function<void(const RemoteSimulation&, int ranks)>& drive,
                             const std::function<Evaluate()>& make_evaluate) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (ranks > 1 && provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    if (rank != 0) return ranks;
    throw io::IoError("the MPI library does not support MPI_THREAD_FUNNELED, needed to diagnose on several ranks");
  }
  if (rank != 0) {
    serving_rank(make_evaluate);
    MPI_Finalize();
    return ranks;
  }
  Pool pool(ranks);
  const RemoteSimulation remote = [&pool](const model::SimulationConfig& c, bool keep) { return pool.remote(c, keep); };
  std::atomic<bool> done{false};
  std::exception_ptr error;
  std::thread diagnosis([&] {
    try {
      drive(ranks > 1 ? remote : RemoteSimulation{}, ranks);
    } catch (...) {
      error = std::current_exception();
    }
    done = true;
  });
  try {
    pool.pump(done);
  } catch (const std::exception& e) {
    // A protocol error: requests may wait forever, so no orderly shutdown is possible.
    std::fprintf(stderr, "%sdiagnose: %s; aborting all ranks\n", io::kErrorPrefix, e.what());
    MPI_Abort(MPI_COMM_WORLD, io::to_int(io::ExitCode::IoFailure));
  }
  diagnosis.join();
  pool.stop_all();
  MPI_Finalize();
  if (error) std::rethrow_exception(error);
  return ranks;
}

} // namespace pw::sweep
