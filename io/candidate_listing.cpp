#include "io/candidate_listing.hpp"

#include "diagnose/candidates/candidate.hpp"
#include "diagnose/kinematics.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace pw::io {
namespace dg = pw::diagnose;

namespace {
std::string role_of(const dg::Candidate& c) {
  if (c.nuisance()) return "nuisance";
  if (c.calibration_only()) return "calibration only";
  if (c.rig_design()) return "rig element";
  return "fault";
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}
} // namespace

std::vector<CandidateListing> candidate_listing() {
  std::vector<CandidateListing> out;
  for (const auto& c : dg::candidate_library()) {
    CandidateListing row{.name = c->name(), .role = role_of(*c), .families = {}, .finding_class = "",
                         .physics = c->physics()};
    for (dg::Component f : c->families()) row.families.emplace_back(dg::to_string(f));
    if (const auto fc = c->finding_class()) row.finding_class = fc->name;
    out.push_back(std::move(row));
  }
  return out;
}

std::string candidates_json() {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& r : candidate_listing())
    a.push_back({{"name", r.name},
                 {"role", r.role},
                 {"families", r.families},
                 {"finding_class", r.finding_class},
                 {"physics", r.physics}});
  return a.dump(1) + "\n";
}

std::string candidates_text() {
  std::string s;
  char line[256];
  std::snprintf(line, sizeof line, "%-26s %-17s %-14s %-22s %s\n", "candidate", "role", "families", "class",
                "physics");
  s += line;
  for (const auto& r : candidate_listing()) {
    std::snprintf(line, sizeof line, "%-26s %-17s %-14s %-22s ", r.name.c_str(), r.role.c_str(),
                  joined(r.families).c_str(), r.finding_class.empty() ? "-" : r.finding_class.c_str());
    s += line + r.physics + "\n";
  }
  return s;
}

} // namespace pw::io
