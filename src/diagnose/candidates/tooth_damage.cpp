// Local tooth damage (crack, chip) on one tooth of the sun, of a planet or of
// the ring: that tooth's mesh stiffness is multiplied by a factor < 1
// (imperfections.teeth, stiffness_factor). Which tooth comes from the peak
// of the residual's synchronous average (locate.hpp) through the assembly
// phases (ToothMap); the neighbours are screened too because the peak of a
// softened pair spreads over the contact ratio (~1.6 mesh cycles).
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

const char* body_name(model::Body b) {
  switch (b) {
  case model::Body::Sun: return "sun";
  case model::Body::Planet: return "planet";
  case model::Body::Ring: return "ring";
  }
  return "?";
}

class ToothDamage final : public Candidate {
public:
  explicit ToothDamage(model::Body body) : body_(body) {}
  std::string name() const override { return std::string(body_name(body_)) + "_tooth_damage"; }
  std::string physics() const override {
    return std::string("one ") + body_name(body_) +
           " tooth is softened (crack or chip): its pair stiffness drops each time it meshes, once per " +
           (body_ == model::Body::Sun      ? "planet pass of the sun tooth"
            : body_ == model::Body::Planet ? "planet revolution on each of its two meshes"
                                           : "planet pass over the ring tooth");
  }
  std::vector<Component> families() const override {
    switch (body_) {
    case model::Body::Sun: return {Component::Sun};
    case model::Body::Planet: return {Component::Planet};
    case model::Body::Ring: return {Component::Carrier};
    }
    return {};
  }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig&) const override {
    return {{"stiffness_factor", "1", 0.05, 1.0, false, 0.7}};
  }
  std::vector<Variant> variants(const LocatedEvidence& ev, const model::SimulationConfig& base,
                                const ToothMap& map) const override {
    const Component fam = families().front();
    const int f = static_cast<int>(fam);
    const double u = ev.peak_mesh_cycle[f];
    const int z = map.teeth(body_);
    std::vector<Variant> out;
    auto add = [&](int planet, int tooth) {
      Variant v;
      v.body = body_;
      v.planet = body_ == model::Body::Planet ? planet : 0;
      v.tooth = ((tooth % z) + z) % z;
      v.label = std::string(body_name(body_)) + (body_ == model::Body::Planet ? " " + std::to_string(planet) : "") +
                " tooth " + std::to_string(v.tooth);
      for (const auto& o : out)
        if (o.planet == v.planet && o.tooth == v.tooth) return;
      out.push_back(v);
    };
    const int p = ev.peak_planet[f];
    if (body_ == model::Body::Sun) {
      const int j = map.nearest_tooth(body_, p, ToothMap::Mesh::SunPlanet, u);
      add(0, j); add(0, j - 1); add(0, j + 1);
    } else if (body_ == model::Body::Ring) {
      const int j = map.nearest_tooth(body_, p, ToothMap::Mesh::PlanetRing, u);
      add(0, j); add(0, j - 1); add(0, j + 1);
    } else {
      // The peak in planet p's sun-mesh channel is most likely planet p's own tooth; other planets'
      // teeth reach that channel through the sun and carrier.
      const auto mesh = ev.peak_from_ring_mesh[f] ? ToothMap::Mesh::PlanetRing : ToothMap::Mesh::SunPlanet;
      for (int k = 0; k < base.stage.planet_count; ++k) {
        const int planet = (p + k) % base.stage.planet_count;
        const int j = map.nearest_tooth(body_, planet, mesh, u);
        add(planet, j);
        if (k == 0) { add(planet, j - 1); add(planet, j + 1); }
      }
    }
    return out;
  }
  void apply(model::SimulationConfig& c, const Variant& v, std::span<const double> x,
             std::vector<std::string>* o) const override {
    model::ToothModifier t;
    t.body = body_;
    t.planet = v.planet;
    t.tooth = v.tooth;
    t.stiffness_factor = std::clamp(x[0], 1e-6, 1.0);
    c.imperfections.teeth.push_back(t);
    if (o)
      o->push_back("imperfections.teeth=[{body=\"" + std::string(body_name(body_)) + "\",planet=" +
                   std::to_string(t.planet) + ",tooth=" + std::to_string(t.tooth) +
                   ",stiffness_factor=" + format_value(t.stiffness_factor) + "}]");
  }

private:
  model::Body body_;
};
} // namespace
std::unique_ptr<Candidate> sun_tooth_damage() { return std::make_unique<ToothDamage>(model::Body::Sun); }
std::unique_ptr<Candidate> planet_tooth_damage() { return std::make_unique<ToothDamage>(model::Body::Planet); }
std::unique_ptr<Candidate> ring_tooth_damage() { return std::make_unique<ToothDamage>(model::Body::Ring); }
} // namespace pw::diagnose::candidates
