# Reduced-model speed/accuracy bench (issue 3; included by bench/CMakeLists.txt
# when BRIDGEFIT_BUILD_BENCH=ON). Run: bf_models_bench docs/reduced_bench
add_executable(bf_models_bench ${CMAKE_CURRENT_LIST_DIR}/models_reduced_bench.cpp)
target_link_libraries(bf_models_bench PRIVATE bf_models OpenMP::OpenMP_CXX)
