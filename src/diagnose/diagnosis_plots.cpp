#include "diagnose/diagnosis_plots.hpp"

#include <cmath>
#include <optional>
#include <string>

namespace pw::diagnose {

namespace {

/// Amplitude spectrum of channel c: the recording's held-out half and the models before/after.
PlotSeries spectrum_series(const Diagnosis& d, const ModelComparison& cmp, std::size_t c, const std::string& unit,
                           const ReportedModels& m) {
  const RecordingSpectra& sp = cmp.spectra();
  const double R = sp.layout.window_revolutions;
  PlotSeries ps;
  ps.name = "spectrum/" + d.channels[c];
  ps.kind = "spectrum";
  ps.x_label = "carrier order";
  ps.y_label = "amplitude [" + unit + "]";
  std::vector<double> rec, bef, aft;
  for (int k = 1; k <= sp.layout.max_bin; ++k) {
    const std::size_t b = static_cast<std::size_t>(k);
    ps.x.push_back(static_cast<double>(k) / R);
    rec.push_back(sp.amplitude[1][c][b]);
    bef.push_back(d.nuisance.gains[c] * m.nominal[c][b]);
    aft.push_back(m.final_gains[c] * m.final_model[c][b]);
  }
  ps.columns = {{"recording", rec}, {"model_before", bef}, {"model_after", aft}};
  return ps;
}

/// Whitened held-out residual per feature cell of channel c for the three models.
PlotSeries residual_series(const Diagnosis& d, const ModelComparison& cmp, std::size_t c, const WindowScore& nominal,
                           const WindowScore& nuisance, const WindowScore& after, const WindowScore* lead) {
  const RecordingSpectra& sp = cmp.spectra();
  const int ncell = cmp.cells();
  PlotSeries pr;
  pr.name = "residual/" + d.channels[c];
  pr.kind = "residual";
  pr.x_label = "carrier order";
  pr.y_label = "whitened residual rho (held-out half)";
  std::vector<double> rb, rn, ra, rl;
  for (int i = 0; i < ncell; ++i) {
    const std::size_t f = static_cast<std::size_t>(static_cast<int>(c) * ncell + i);
    pr.x.push_back(sp.layout.cells[static_cast<std::size_t>(i)].order);
    rb.push_back(nominal.rho[f]);
    rn.push_back(nuisance.rho[f]);
    ra.push_back(after.rho[f]);
    if (lead) rl.push_back(lead->rho[f]);
  }
  pr.columns = {{"nominal", rb}, {"nuisance_fitted", rn}, {"final", ra}};
  if (lead) pr.columns.emplace_back("lead_not_named", std::move(rl));
  return pr;
}

/// The features themselves (not plotted): amplitudes of both halves and of the models.
PlotSeries feature_table(const Diagnosis& d, const ModelComparison& cmp, std::size_t c, const std::string& unit,
                         const ReportedModels& m) {
  const RecordingSpectra& sp = cmp.spectra();
  const int ncell = cmp.cells();
  PlotSeries pt;
  pt.name = "features/" + d.channels[c];
  pt.kind = "table";
  pt.x_label = "carrier order";
  pt.y_label = "amplitude [" + unit + "]";
  std::vector<double> r0, r1, mn, mu, mf, ml, sd, ns;
  for (int i = 0; i < ncell; ++i) {
    const int f = static_cast<int>(c) * ncell + i;
    const std::size_t b = static_cast<std::size_t>(sp.layout.cells[static_cast<std::size_t>(i)].bin);
    pt.x.push_back(sp.layout.cells[static_cast<std::size_t>(i)].order);
    r0.push_back(cmp.recording_amplitude(0, f));
    r1.push_back(cmp.recording_amplitude(1, f));
    mn.push_back(d.nuisance.gains[c] * m.nominal[c][b]);
    mu.push_back(d.nuisance.gains[c] * m.nuisance[c][b]);
    mf.push_back(m.final_gains[c] * m.final_model[c][b]);
    if (m.lead) ml.push_back((*m.lead_gains)[c] * (*m.lead)[c][b]);
    sd.push_back(std::sqrt(cmp.noise_variance(f)));
    ns.push_back(std::sqrt(cmp.nonstationary_variance(f)));
  }
  pt.columns = {{"recording_fit", r0}, {"recording_held_out", r1}, {"model_nominal", mn},
                {"model_nuisance", mu}, {"model_final", mf}, {"noise_rms", sd}, {"nonstationary_sd", ns}};
  if (m.lead) pt.columns.emplace_back("model_lead_not_named", std::move(ml));
  return pt;
}

} // namespace

void tabulate_plots(Diagnosis& d, const ModelComparison& cmp, const Recording& recording, const ReportedModels& m) {
  const RecordingSpectra& sp = cmp.spectra();
  const WindowScore nominal = cmp.score(m.nominal, Half::HeldOut, d.nuisance.gains, HousingGains::Given);
  const WindowScore nuisance = cmp.score(m.nuisance, Half::HeldOut, d.nuisance.gains, HousingGains::Given);
  const WindowScore after = cmp.score(m.final_model, Half::HeldOut, m.final_gains, HousingGains::Given);
  std::optional<WindowScore> lead;
  if (m.lead) lead = cmp.score(*m.lead, Half::HeldOut, *m.lead_gains, HousingGains::Given);
  for (int ch = 0; ch < cmp.channels(); ++ch) {
    const std::size_t c = static_cast<std::size_t>(ch);
    const std::string unit = recording.channels[static_cast<std::size_t>(sp.channels[c])].unit;
    d.plots.push_back(spectrum_series(d, cmp, c, unit, m));
    d.plots.push_back(residual_series(d, cmp, c, nominal, nuisance, after, lead ? &*lead : nullptr));
    d.plots.push_back(feature_table(d, cmp, c, unit, m));
  }
  for (const auto& re : d.location.rotations) {
    if (re.tsa.empty()) continue;
    PlotSeries ps;
    ps.name = std::string("tsa/") + to_string(re.component) + "/" + re.channel;
    ps.kind = "tsa";
    ps.x_label = "mesh cycles from the recording's start (mod " + std::to_string(re.period_mesh_cycles) + ")";
    ps.y_label = "synchronous average of the recording";
    std::vector<double> v;
    for (std::size_t j = 0; j < re.tsa.size(); ++j) {
      ps.x.push_back(static_cast<double>(j) / re.samples_per_cycle);
      v.push_back(re.tsa[j]);
    }
    ps.columns = {{"recording", v}};
    d.plots.push_back(std::move(ps));
  }
}

} // namespace pw::diagnose
