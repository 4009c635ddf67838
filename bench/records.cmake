# R curves from ~100,000-row records (issue 15): time and peak memory per
# method; bench/rcurve_rows_bench.sh adds the CLI's load-displacement fit.
# Run: bf_rcurve_rows_bench [rows=100000] [record_out.csv]
add_executable(bf_rcurve_rows_bench ${CMAKE_CURRENT_LIST_DIR}/rcurve_rows_bench.cpp)
target_link_libraries(bf_rcurve_rows_bench PRIVATE bf_experiment bf_io)
target_compile_definitions(bf_rcurve_rows_bench PRIVATE
  BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
