# Optimizer comparison and full-fit timing (issue 7). Run: bf_inverse_bench docs/fit_bench
add_executable(bf_inverse_bench ${CMAKE_CURRENT_LIST_DIR}/inverse_optimizers.cpp)
target_link_libraries(bf_inverse_bench PRIVATE bf_inverse bf_models bf_io)
target_compile_definitions(bf_inverse_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
# sigma_c's error over many noise draws of the truncated case (issue 7, bias check).
# Run: bf_fit_noise_bench [resolution_mm=1] [draws=100] [first_seed=1] [profile=0] [out.csv] [starts=3]
add_executable(bf_fit_noise_bench ${CMAKE_CURRENT_LIST_DIR}/fit_noise_draws.cpp)
target_link_libraries(bf_fit_noise_bench PRIVATE bf_inverse bf_models bf_io)
target_compile_definitions(bf_fit_noise_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
# The load-displacement fit's sigma_c error against element size and time.
# Run: bf_fit_load_bench docs/bench/fit_load_bench [draws=10] [sizes_mm=2,1,0.5]
add_executable(bf_fit_load_bench ${CMAKE_CURRENT_LIST_DIR}/fit_load_bench.cpp)
target_link_libraries(bf_fit_load_bench PRIVATE bf_pipeline bf_inverse bf_models bf_scene)
# A default R-curve fit with profiles at --resolution auto and at fixed sizes:
# wall time against error on the issue-7 cases and the MDF sample (issue 17).
# Run: bf_fit_resolution_bench docs/bench/fit_resolution_bench [sizes_mm=4,2,1,0.5,0.25] [seed=1]
add_executable(bf_fit_resolution_bench ${CMAKE_CURRENT_LIST_DIR}/fit_resolution_bench.cpp)
target_link_libraries(bf_fit_resolution_bench PRIVATE bf_pipeline bf_inverse bf_models bf_io bf_scene)
target_compile_definitions(bf_fit_resolution_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
