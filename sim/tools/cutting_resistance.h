#pragma once

// The force a tissue puts up against a blade cutting it, in the fracture-mechanics view of
// cutting: the work the blade does goes into the new surface it opens (the energy balance of
// Griffith's criterion: a crack advances when the work supplied pays for its new surface). The
// tissue's toughness G is that energy per unit area of cut [J/m^2]. A blade edge with `depth` of
// its length in the tissue, moving across the edge by dx, opens the area depth |dx| and must do
// the work G depth |dx|; the force that does it is
//   F = -G depth w / |w|,   w = v - (v . e) e   (the blade's velocity across its edge e),
// so F . v = -G depth |w| = -G dA/dt: it only ever takes energy (passive). Motion along the edge (a
// blade pushed in point first, or drawn out along its own axis) opens no new surface in this view
// and meets no resistance here; a blade moving across its edge meets F = -G depth v / |v|.
// Two changes to that law, both keeping F . v <= 0 for every input:
//   - below ramp_speed v0 the force fades linearly to zero with the speed, F = -G depth w / v0 (a
//     viscous drag of G depth / v0 [N s/m]): for a hand holding still the direction of w is
//     tremor and sensor noise, and a force of full size flipping with it would chatter;
//   - its size is capped at max_force.
// In short, F = -min(G depth, max_force) w / max(|w|, v0).
//
// Inputs
//   toughness  G [J/m^2 = N/m], >= 0
//   depth      the length of the blade's edge inside the tissue [m], >= 0
//   velocity   v, the blade's velocity [m/s]
//   edge       e, the direction of the blade's edge, unit (its sign does not matter)
//   settings   ramp_speed v0 [m/s] > 0, max_force [N] > 0
// Output: the force on the blade [N].
// Throws std::invalid_argument for a negative or non-finite toughness or depth, a non-finite
// velocity, an edge not of unit length (off by more than 1e-6), or settings out of range.

#include "sim/core/types.h"

namespace incise::sim::tools {

// The toughness of a soft, liver-like tissue [J/m^2]: the order of magnitude of needle-insertion
// and blade-cutting measurements on animal liver (roughly 80 to 230 J/m^2; docs/cutting.md,
// "What the hand feels", says where from and how rough this is).
inline constexpr Real kDefaultToughness = 200;

struct CuttingResistanceSettings {
  // [m/s] > 0: below this speed across the edge the force fades to zero. A scalpel stroke runs
  // at centimetres per second (the liver script's at 11 cm/s); a hand holding still trembles at
  // millimetres per second.
  Real ramp_speed = 0.01;
  // [N] > 0: the most the blade is held back, a desktop haptic device's range (the probe's
  // max_force, probe.h).
  Real max_force = 4;
};

Vec3 cutting_resistance(Real toughness, Real depth, const Vec3& velocity, const Vec3& edge,
                        const CuttingResistanceSettings& settings = {});

}  // namespace incise::sim::tools
