# MPM speed/accuracy bench (included by bench/CMakeLists.txt when
# BRIDGEFIT_BUILD_BENCH=ON).
add_executable(bf_mpm_bench ${CMAKE_CURRENT_LIST_DIR}/mpm_bench.cpp)
target_link_libraries(bf_mpm_bench PRIVATE bf_mpm bf_scene bf_core)
# MPM crack growth with bridging against the reduced model (issue 5).
add_executable(bf_mpm_growth_bench ${CMAKE_CURRENT_LIST_DIR}/mpm_growth_bench.cpp)
target_link_libraries(bf_mpm_growth_bench PRIVATE bf_mpm bf_models bf_laws bf_scene bf_core
                                                   fmt::fmt)
