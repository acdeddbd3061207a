#pragma once
// Seed 004's spring-calibration experiment, as the benchmark, the tests and the demo data use it:
// a 1 cm cube of density 1040 kg/m^3 with its bottom face fixed; a force of 0.001 N pushes, in
// turn, the central node of each of the five free faces inwards for 0.2 s, sampled 200 times.
// The seed's cube was an irregular mesh of 120 nodes, 377 tets and 590 springs; ours is the
// regular 4 x 4 x 4 grid of make_box_mesh (125 nodes, 320 tets, 540 springs), whose faces each
// have a central node. The seed gives E = 3.6 Pa, under which 1 mN would push a node of this cube
// several centimetres (the cube is 1 cm): we read it as 3.6 kPa, a soft tissue's modulus.

#include "sim/calibrate/probe_data.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::sim::calibrate {

inline constexpr Real kCubeEdge = 0.01;     // [m]
inline constexpr Real kCubeDensity = 1040;  // [kg/m^3]
inline constexpr Real kCubeModulus = 3600;  // [Pa], the reference
inline constexpr Real kCubeForce = 0.001;   // [N]
inline constexpr Real kCubePushTime = 0.2;  // [s]
inline constexpr int kCubeSamples = 200;    // per push, after the start

struct CubeExperiment {
  Scene scene;  // the mass-spring cube, bottom fixed, E = youngs_modulus
  TetMesh mesh;
  ProbeData pushes;  // the five pushes; positions all at the start (simulate_probe_data fills)
};

// The cube with a homogeneous modulus [Pa] (damping: a fraction 0.5 of eq. 7's), on a grid of
// cells^3 (even, so that each face has a central node; 4 is the experiment, 2 a quick one).
// Throws std::invalid_argument for an odd or non-positive cells.
CubeExperiment seed004_cube(Real youngs_modulus, int cells = 4);

}  // namespace incise::sim::calibrate
