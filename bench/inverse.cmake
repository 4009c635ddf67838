# Optimizer comparison and full-fit timing (issue 7). Run: bf_inverse_bench docs/fit_bench
add_executable(bf_inverse_bench ${CMAKE_CURRENT_LIST_DIR}/inverse_optimizers.cpp)
target_link_libraries(bf_inverse_bench PRIVATE bf_inverse bf_models bf_io)
target_compile_definitions(bf_inverse_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
