// Wear of every tooth flank's microelements, accumulated from the dynamic
// contact forces during a window of mesh cycles and extrapolated over many
// cycles (docs/derivation.md §5).
//
// Flank families (index f): 0 = sun drive flanks; 1..N = planet i, sun side;
// N+1..2N = planet i, ring side; 2N+1 = ring. Mesh m = 2i (sun-planet i) wears
// families 0 and 1+i; mesh m = 2i+1 (planet-ring i) wears 1+N+i and 2N+1.
//
// Wear is booked per *completed* contact pass: a tooth pair's wear is held
// until the pair leaves contact, then added to both teeth with one pass each.
// Passes already under way when the window opens or still under way when it
// closes are dropped, so each tooth's wear per pass is unbiased by the window
// edges.
#pragma once

#include "model/planetary_system.hpp"

#include <array>
#include <vector>

namespace pw::wear {

class FlankWearAccumulator {
public:
  /// `kappa_m2_N` Archard coefficient; geometry and flank grids from `sys`;
  /// face widths from `config` (the narrower gear of each mesh carries).
  FlankWearAccumulator(const model::PlanetaryDynamics& sys, const model::SimulationConfig& config,
                       double kappa_m2_N);

  int families() const { return static_cast<int>(fam_.size()); }
  /// Starts a window: clears accumulated wear and pass counts; pairs in
  /// contact now are marked partial and will not be booked.
  void begin_window();
  /// Books the wear of time step dt from the system's current mesh states.
  void accumulate(double dt_s);

  /// Wear per mesh cycle of the stage [m/cycle] of family f, teeth x
  /// elements row-major: (wear per pass) x (passes per mesh cycle: N/Zs for
  /// the sun, 1/Zp for a planet flank, N/Zr for the ring). Teeth without a
  /// complete pass in the window get the mean of the family's teeth that had
  /// one. Returns false if no tooth of the family completed a pass.
  bool wear_rate_per_cycle(int f, std::vector<double>& out) const;

  /// Completed passes of family f's teeth in the current window.
  const std::vector<int>& passes(int f) const { return fam_[f].passes; }
  model::FlankSet& flank_set(model::ToothSurfaces& s, int f) const;

private:
  struct Family {
    int teeth = 0, elements = 0;
    std::vector<double> arc_length_m;  ///< involute arc of each element [m]
    std::vector<double> wear_m;        ///< booked wear, teeth x elements
    std::vector<int> passes;
    double passes_per_cycle = 0;
  };
  /// A pair in contact: per element, the Archard load kappa F' |v_s| dt summed over its steps
  /// so far [m^2] (W2 before the division by the element's arc length, which book() applies
  /// once per pass instead of at every step). On a mesh whose two flank grids are the same
  /// (same_grid_) both flanks' loads are in `wa` and `wb` stays empty.
  struct Pending {
    bool partial = false;  ///< under way when the window opened: never booked
    int tooth_a = -1, tooth_b = -1;
    std::vector<double> wa, wb;
  };
  /// A mesh's passes under way: pairs first .. first + count - 1 of the run (MeshState::first_pair),
  /// pair n in slot[n mod kMaxPairs]. The window holds consecutive pairs, at most kMaxPairs, so
  /// the pairs of one step never share a slot; a pair that left is booked before one that
  /// entered takes its slot.
  struct MeshPasses {
    long long first = 0;
    int count = 0;
    std::array<Pending, model::MeshState::kMaxPairs> slot;
    bool holds(long long n) const { return n >= first && n < first + count; }
    Pending& at(long long n) {
      constexpr long long S = model::MeshState::kMaxPairs;
      return slot[static_cast<std::size_t>(((n % S) + S) % S)];
    }
  };
  /// The window of one mesh moved to pairs first .. first + ms.pairs - 1: books the passes that
  /// left it (families fa, fb; `shared`: one element grid for both flanks) and starts those
  /// that entered.
  void update_passes(MeshPasses& mp, const model::MeshState& ms, long long first, int fa, int fb, bool shared);
  /// Adds one completed pass of `tooth` of family `fam`: its loads per element `w` [m^2] over
  /// the elements' arc lengths.
  void book(int fam, int tooth, const std::vector<double>& w);

  const model::PlanetaryDynamics& sys_;
  double kappa_ = 0;
  double width_sp_m_ = 0, width_pr_m_ = 0;
  int planets_ = 0;
  bool window_start_ = true;
  std::vector<Family> fam_;
  std::vector<MeshPasses> pending_;           ///< per mesh
  std::vector<char> same_grid_;                ///< per mesh: its flanks share one element grid
};

} // namespace pw::wear
