# A campaign of 8 synthetic CT specimens on 1 and 2 threads, and the joint
# fit's time against the single fits (issue 19). Run: bf_campaign_bench docs/bench/campaign_bench
add_executable(bf_campaign_bench ${CMAKE_CURRENT_LIST_DIR}/campaign_bench.cpp)
target_link_libraries(bf_campaign_bench PRIVATE bf_campaign bf_pipeline bf_io bf_scene)
