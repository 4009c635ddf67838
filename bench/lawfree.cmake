# Law-free route error split (docs/LAW_FREE.md, "Where the pointwise error
# comes from"): bench/lawfree_split DIR SCENE on a synth --bridged-field
# run's images/truth.csv and dic.h5.
add_executable(lawfree_split ${CMAKE_CURRENT_LIST_DIR}/lawfree_split.cpp)
target_link_libraries(lawfree_split PRIVATE bf_pipeline bf_io fmt::fmt)
# ... and where its per-frame J_ff scatter comes from (DIC field against the
# generator's exact field, DIC tip against the true tip).
add_executable(lawfree_exact_j ${CMAKE_CURRENT_LIST_DIR}/lawfree_exact_j.cpp)
target_link_libraries(lawfree_exact_j PRIVATE bf_pipeline bf_io fmt::fmt)
# ... and what in the DIC makes it (speckle pattern, image noise) on a K field.
add_executable(lawfree_j_noise ${CMAKE_CURRENT_LIST_DIR}/lawfree_j_noise.cpp)
target_link_libraries(lawfree_j_noise PRIVATE bf_pipeline bf_io fmt::fmt)
