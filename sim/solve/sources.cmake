# The solvers beyond symplectic Euler (which sim/CMakeLists.txt lists itself). Paths relative to sim/.
set(INCISE_SIM_SOLVE_SOURCES ${INCISE_SIM_SOLVE_SOURCES}
  solve/active_region.cpp
  solve/adaptive_explicit.cpp
  solve/block_incomplete_cholesky.cpp
  solve/block_sparse.cpp
  solve/central_difference.cpp
  solve/constrained_system.cpp
  solve/free_coordinates.cpp
  solve/implicit_euler.cpp
  solve/stable_time_step.cpp
  solve/static_solver.cpp
)
