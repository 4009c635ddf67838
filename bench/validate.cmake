# Issue 17's validation campaign (docs/VALIDATION.md). One command:
#   bash bench/validate/run.sh [cases=300] [seed=17] [jobs=2]
# or bf_validate [cases] [seed] [jobs] [out_dir] [first].
include(${CMAKE_CURRENT_LIST_DIR}/validate/validation_lib.cmake)
find_package(Threads REQUIRED)
add_executable(bf_validate ${CMAKE_CURRENT_LIST_DIR}/validate/bf_validate.cpp)
target_link_libraries(bf_validate PRIVATE bf_validation Threads::Threads)
