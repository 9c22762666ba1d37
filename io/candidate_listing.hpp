// The diagnosis's candidate library (diagnose/candidates) as text for people and programs,
// `planetwear candidates [--format text|json]`: each candidate's name, its role in a diagnosis,
// the line families its signature lives in, the class of findings it belongs to and its
// physics in one sentence. What a report's "located in the sun family" can stand for, and what
// a script scoring reports against known effects maps them with.
#pragma once

#include <string>
#include <vector>

namespace pw::io {

/// One row of the listing.
struct CandidateListing {
  std::string name;
  /// "fault" (screened and named as a finding), "nuisance" (fitted first, in every fit),
  /// "rig element" (a property of the rig's design: named only without a calibration) or
  /// "calibration only" (fitted by `calibrate --rig-elements`, never screened as a finding).
  std::string role;
  std::vector<std::string> families;  ///< Component names ("mesh", "sun", ...), the first the primary
  std::string finding_class;          ///< "" when the candidate belongs to no class
  std::string physics;
};

/// Every candidate of the library, in the library's order.
std::vector<CandidateListing> candidate_listing();

/// JSON array of {"name", "role", "families", "finding_class", "physics"} objects.
std::string candidates_json();

/// A table: name, role, families, class, then the physics on the same line.
std::string candidates_text();

} // namespace pw::io
