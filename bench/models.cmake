# Reduced-model speed/accuracy bench (issue 3; included by bench/CMakeLists.txt
# when BRIDGEFIT_BUILD_BENCH=ON). Run: bf_models_bench docs/reduced_bench
add_executable(bf_models_bench ${CMAKE_CURRENT_LIST_DIR}/models_reduced_bench.cpp)
target_link_libraries(bf_models_bench PRIVATE bf_models OpenMP::OpenMP_CXX)
# Forward runs as a fit makes them (one model, many laws): time per run and
# every point written for a number-by-number comparison of two builds.
# Run: bf_reduced_forward_bench OUT [resolution_mm=0.5] [reps=20] [solver]
add_executable(bf_reduced_forward_bench ${CMAKE_CURRENT_LIST_DIR}/reduced_forward_check.cpp)
target_link_libraries(bf_reduced_forward_bench PRIVATE bf_models bf_io)
target_compile_definitions(bf_reduced_forward_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
