#include "io/csv_writer.hpp"

#include "io/atomic_output.hpp"
#include "io/io_error.hpp"

#include "core/error.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <ostream>
#include <stdexcept>

namespace pw::io {
namespace {

/// RFC 4180 quoting, only where needed.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void put_number(std::ostream& out, double v) {
  if (std::isnan(v)) {
    out << "nan";
    return;
  }
  std::array<char, 64> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.write(buf.data(), result.ptr - buf.data());
}

} // namespace

void write_csv(std::ostream& out, const model::SimulationResult& result, const CsvOptions& options) {
  std::vector<const model::Channel*> columns;
  if (options.channels.empty()) {
    for (const auto& c : result.channels) columns.push_back(&c);
  } else {
    for (const auto& name : options.channels) {
      const model::Channel* c = result.find(name);
      if (!c) {
        std::string available;
        for (const auto& ch : result.channels) available += (available.empty() ? "" : ", ") + ch.name;
        throw InputError(name, "no such channel; available: " + available);
      }
      columns.push_back(c);
    }
  }
  for (const auto* c : columns)
    if (c->values.size() != result.time_s.size())
      throw std::invalid_argument("channel '" + c->name + "' has " + std::to_string(c->values.size()) +
                                  " samples but time_s has " + std::to_string(result.time_s.size()));

  out << "time_s";
  for (const auto* c : columns) out << ',' << csv_field(c->name + " [" + c->unit + "]");
  out << '\n';
  for (std::size_t i = 0; i < result.time_s.size(); ++i) {
    put_number(out, result.time_s[i]);
    for (const auto* c : columns) {
      out << ',';
      put_number(out, c->values[i]);
    }
    out << '\n';
  }
}

void write_csv(const std::filesystem::path& path, const model::SimulationResult& result, const CsvOptions& options) {
  AtomicOutput output(path);
  {
    std::ofstream file(output.temp_path(), std::ios::binary | std::ios::trunc);
    if (!file) throw IoError(output.temp_path().string() + ": cannot create file");
    write_csv(file, result, options);
    file.close();
    if (!file) throw IoError(output.temp_path().string() + ": write failed (disk full?)");
  }
  output.commit();
}

} // namespace pw::io
