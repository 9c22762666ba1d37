#include "io/exit_code.hpp"

#include "core/error.hpp"
#include "io/io_error.hpp"

namespace pw::io {

ExitCode exit_code_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError&) {
    return ExitCode::BadInput;
  } catch (const SolverError&) {
    return ExitCode::SolverFailure;
  } catch (const IoError&) {
    return ExitCode::IoFailure;
  } catch (...) {
    return ExitCode::Internal;
  }
}

std::string error_message(const std::exception_ptr& e) {
  const std::string prefix = kErrorPrefix;
  try {
    std::rethrow_exception(e);
  } catch (const InputError& x) {
    return prefix + x.what();
  } catch (const SolverError& x) {
    return prefix + "solver failed: " + x.what();
  } catch (const IoError& x) {
    return prefix + "I/O: " + x.what();
  } catch (const std::exception& x) {
    return prefix + "internal error (please report): " + x.what();
  } catch (...) {
    return prefix + "internal error (please report): unknown exception";
  }
}

} // namespace pw::io
