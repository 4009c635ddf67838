# DIC speed-vs-accuracy bench (included by bench/CMakeLists.txt when
# BRIDGEFIT_BUILD_BENCH=ON).
add_executable(dic_speed ${CMAKE_CURRENT_LIST_DIR}/dic_speed.cpp)
target_link_libraries(dic_speed PRIVATE bf_dic OpenMP::OpenMP_CXX)
target_compile_definitions(dic_speed PRIVATE BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_executable(dic_sample15 ${CMAKE_CURRENT_LIST_DIR}/dic_sample15.cpp)
target_link_libraries(dic_sample15 PRIVATE bf_dic)
target_compile_definitions(dic_sample15 PRIVATE BRIDGEFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_executable(dic_band_frames ${CMAKE_CURRENT_LIST_DIR}/dic_band_frames.cpp)
target_link_libraries(dic_band_frames PRIVATE bf_dic)
add_executable(dic_speckle_speed ${CMAKE_CURRENT_LIST_DIR}/dic_speckle_speed.cpp)
target_link_libraries(dic_speckle_speed PRIVATE bf_dic OpenMP::OpenMP_CXX)
