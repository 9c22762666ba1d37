// The diagnosis report (io/diagnosis_report.*) links only files it wrote:
// every relative link and image of report.md and report.html names a file in
// the report directory, with and without plots drawn.
#include "io/diagnosis_report.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Relative targets of Markdown links/images "](x)" and HTML src="x" / href="x".
std::set<std::string> local_targets(const std::string& text) {
  std::set<std::string> out;
  const std::regex md(R"(\]\(([^)\s]+)\))"), html(R"((?:src|href)=\"([^\"]+)\")");
  for (const std::regex* re : {&md, &html})
    for (auto it = std::sregex_iterator(text.begin(), text.end(), *re); it != std::sregex_iterator(); ++it) {
      const std::string t = (*it)[1];
      if (t.rfind("http", 0) != 0 && t.rfind("#", 0) != 0 && t.rfind("data:", 0) != 0) out.insert(t);
    }
  return out;
}

pw::diagnose::Diagnosis with_one_plot() {
  pw::diagnose::Diagnosis d;
  d.summary = "No missing physics found.";
  d.plots.push_back({"spectrum/w_sun", "spectrum", "carrier order", "amplitude [rad/s]", {1, 2},
                     {{"recording", {0.1, 0.2}}}});
  return d;
}

void expect_links_resolve(const fs::path& dir) {
  for (const char* doc : {"report.md", "report.html"})
    for (const std::string& t : local_targets(read(dir / doc)))
      EXPECT_TRUE(fs::exists(dir / t)) << doc << " links " << t << ", which was not written";
}

} // namespace

TEST(DiagnosisReport, WithoutPlotsLinksNoImageAndSaysWhy) {
  pw::test::TempDir tmp;
  pw::io::ReportContext ctx;
  ctx.plots_available = false;
  ctx.plots_note = "--no-plots was given";
  const auto d = with_one_plot();
  pw::io::write_diagnosis_report(tmp.path(), d, ctx);
  pw::io::write_diagnosis_documents(tmp.path(), d, ctx);
  const std::string md = read(tmp / "report.md");
  EXPECT_EQ(md.find("spectrum_w_sun.png"), std::string::npos);
  EXPECT_EQ(read(tmp / "report.html").find("spectrum_w_sun.png"), std::string::npos);
  EXPECT_NE(md.find("No plots: --no-plots was given"), std::string::npos);
  expect_links_resolve(tmp.path());
}

TEST(DiagnosisReport, WithPlotsLinksEachDrawnImage) {
  pw::test::TempDir tmp;
  pw::io::ReportContext ctx;
  const auto d = with_one_plot();
  pw::io::write_diagnosis_report(tmp.path(), d, ctx);
  std::ofstream(tmp / "spectrum_w_sun.png") << "png";  // what scripts/plot_diagnosis.py draws
  pw::io::write_diagnosis_documents(tmp.path(), d, ctx);
  EXPECT_NE(read(tmp / "report.md").find("spectrum_w_sun.png"), std::string::npos);
  expect_links_resolve(tmp.path());
}

// report.json carries the nuisance-fitted model's noise bounds both ways: the folded quantiles,
// which decide "no missing physics", and the linear ones beside them (docs/diagnose.md §5 step 4),
// each under its own key, so that a reader can compare them without recomputing anything.
TEST(DiagnosisReport, JsonKeepsTheFoldedAndTheLinearNoiseBoundsUnderTheirOwnKeys) {
  pw::test::TempDir tmp;
  pw::io::ReportContext ctx;
  ctx.plots_available = false;
  auto d = with_one_plot();
  d.bound_fit = 2201.5;
  d.bound_held_out = 2203.25;
  d.bound_fit_linear = 2101.5;
  d.bound_held_out_linear = 2103.75;
  pw::io::write_diagnosis_report(tmp.path(), d, ctx);
  const auto j = nlohmann::json::parse(read(tmp / "report.json"));
  const auto& b = j.at("noise_bound");
  EXPECT_EQ(b.at("fit").get<double>(), 2201.5);
  EXPECT_EQ(b.at("held_out").get<double>(), 2203.25);
  EXPECT_EQ(b.at("fit_linear").get<double>(), 2101.5);
  EXPECT_EQ(b.at("held_out_linear").get<double>(), 2103.75);
}

TEST(DiagnosisReport, AClassFindingNamesTheClassAndKeepsItsMembersSizeAndLead) {
  // src/diagnose/verdict.hpp, "class finding": missing_physics is the class, the fitted lead
  // stays under "lead", and the class's size is given in its canonical member's parameters.
  pw::test::TempDir tmp;
  pw::io::ReportContext ctx;
  ctx.plots_available = false;
  auto d = with_one_plot();
  pw::diagnose::CandidateResult lead;
  lead.name = "carrier_runout";
  d.candidates.push_back(lead);
  d.winner = 0;
  d.verdict = pw::diagnose::Verdict::MissingPhysicsFound;
  d.lead.candidate = 0;
  d.lead.named_class = "planet_position_error";
  d.lead.class_members = {"carrier_runout", "pin_error"};
  d.lead.class_posterior = 0.999;
  d.lead.class_covers = {"pin_error", "carrier_runout"};
  d.lead.class_size = {{"pin_error_m[1]", 1.5e-6}, {"pin_error_m[2]", -0.5e-6}};
  d.lead.class_size_unit = "m";
  pw::io::write_diagnosis_report(tmp.path(), d, ctx);
  const auto j = nlohmann::json::parse(read(tmp / "report.json"));
  EXPECT_EQ(j.at("missing_physics").get<std::string>(), "planet_position_error");
  const auto& c = j.at("finding_class");
  EXPECT_EQ(c.at("members").at(1).get<std::string>(), "pin_error");
  EXPECT_EQ(c.at("covers").at(1).get<std::string>(), "carrier_runout");
  EXPECT_EQ(c.at("size").at(0).at("name").get<std::string>(), "pin_error_m[1]");
  EXPECT_EQ(c.at("size").at(1).at("value").get<double>(), -0.5e-6);
  EXPECT_EQ(c.at("size_unit").get<std::string>(), "m");
  EXPECT_EQ(j.at("lead").at("name").get<std::string>(), "carrier_runout");
  d.lead.failed = "its near-alias pin_error explains the excess too";
  pw::test::TempDir tmp_md;
  pw::io::write_diagnosis_report(tmp_md.path(), d, ctx);
  EXPECT_NE(read(tmp_md / "report.md").find("named as its class planet_position_error (carrier_runout or pin_error)"),
            std::string::npos);
  // Without a class the candidate is the name and finding_class is null.
  d.lead.named_class.clear();
  pw::test::TempDir tmp2;
  pw::io::write_diagnosis_report(tmp2.path(), d, ctx);
  const auto j2 = nlohmann::json::parse(read(tmp2 / "report.json"));
  EXPECT_EQ(j2.at("missing_physics").get<std::string>(), "carrier_runout");
  EXPECT_TRUE(j2.at("finding_class").is_null());
}

TEST(DiagnosisReport, ASizesConditionAndATransferParameterReachTheJsonAndTheTable) {
  // A torque ripple named on a rig whose input side the configuration leaves at the seed's law:
  // the fraction is the size only for that input (ParameterSpec::size_conditional_on), the load
  // inertia beside it says how the ripple reaches the sensors (ParameterSpec::transfer). Both
  // statements reach report.json (the winner's fitted_parameters and its candidate entry) and the
  // candidates table of report.md, as the summary carries them (test_verdict.cpp).
  pw::test::TempDir tmp;
  pw::io::ReportContext ctx;
  ctx.plots_available = false;
  auto d = with_one_plot();
  pw::diagnose::CandidateResult ripple;
  ripple.name = "torque_ripple";
  pw::diagnose::FittedParameter fraction;
  fraction.name = "torque_ripple_fraction";
  fraction.unit = "1";
  fraction.value = 0.0192;
  fraction.std_error = 8e-5;
  fraction.size_conditional_on = "the configured input";
  pw::diagnose::FittedParameter inertia;
  inertia.name = "stage.output_inertia_kgm2";
  inertia.unit = "kg m^2";
  inertia.value = 1.02;
  inertia.std_error = 0.007;
  inertia.transfer = true;
  ripple.parameters = {fraction, inertia};
  ripple.own_parameters = 2;
  d.candidates.push_back(ripple);
  d.winner = 0;
  d.verdict = pw::diagnose::Verdict::MissingPhysicsFound;
  d.lead.candidate = 0;
  pw::io::write_diagnosis_report(tmp.path(), d, ctx);
  const auto j = nlohmann::json::parse(read(tmp / "report.json"));
  for (const auto* ps : {&j.at("fitted_parameters"), &j.at("candidates").at(0).at("parameters")}) {
    EXPECT_EQ(ps->at(0).at("size_conditional_on").get<std::string>(), "the configured input");
    EXPECT_FALSE(ps->at(0).contains("transfer"));
    EXPECT_TRUE(ps->at(1).at("transfer").get<bool>());
    EXPECT_FALSE(ps->at(1).contains("size_conditional_on"));
  }
  const std::string md = read(tmp / "report.md");
  EXPECT_NE(md.find("(the size for the configured input)"), std::string::npos) << md;
  EXPECT_NE(md.find("kg m^2 (how it reaches the sensors, not its size)"), std::string::npos) << md;
}
