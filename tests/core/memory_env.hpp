// Sets PLANETWEAR_MEMORY_LIMIT for one test and restores the previous value,
// so that memory-limit tests do not depend on the machine's memory.
#pragma once

#include "core/memory_budget.hpp"

#include <cstdlib>
#include <optional>
#include <string>

namespace pw::test {

class MemoryLimitOverride {
public:
  explicit MemoryLimitOverride(const std::string& value) {
    if (const char* old = std::getenv(kMemoryLimitVariable)) old_ = old;
    setenv(kMemoryLimitVariable, value.c_str(), 1);
  }
  ~MemoryLimitOverride() {
    if (old_) setenv(kMemoryLimitVariable, old_->c_str(), 1);
    else unsetenv(kMemoryLimitVariable);
  }
  MemoryLimitOverride(const MemoryLimitOverride&) = delete;
  MemoryLimitOverride& operator=(const MemoryLimitOverride&) = delete;

private:
  std::optional<std::string> old_;
};

} // namespace pw::test
