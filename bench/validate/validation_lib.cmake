# The validation campaign's library (issue 17): one source for the bench
# (bench/validate.cmake: bf_validate) and the CI subset (tests/validate).
if(NOT TARGET bf_validation)
  add_library(bf_validation STATIC ${CMAKE_CURRENT_LIST_DIR}/validation.cpp
                                   ${CMAKE_CURRENT_LIST_DIR}/validation_report.cpp)
  target_include_directories(bf_validation PUBLIC ${CMAKE_CURRENT_LIST_DIR})
  target_link_libraries(bf_validation PUBLIC bf_pipeline bf_scene PRIVATE bf_dic bf_io bf_specimen fmt::fmt)
endif()
