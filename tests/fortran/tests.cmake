# ctest suite of the Fortran kernel (included from the root CMakeLists.txt).
add_library(ringlube_check STATIC ${CMAKE_CURRENT_LIST_DIR}/check.f90)
target_link_libraries(ringlube_check PUBLIC ringlube_kernel)

foreach(t tridiag tridiag_fixed greenwood_tripp physics_basics reynolds cycle time_order mixed_share film_viscosity)
  add_executable(test_${t} ${CMAKE_CURRENT_LIST_DIR}/test_${t}.f90)
  target_link_libraries(test_${t} PRIVATE ringlube_check ringlube_io ${LAPACK_LIBRARIES})
  add_test(NAME ${t} COMMAND test_${t} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
endforeach()

add_test(NAME bad_decks
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../cli/bad_decks.sh $<TARGET_FILE:ringlube-solve>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME solve_shipped_deck
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../cli/solve_deck.sh $<TARGET_FILE:ringlube-solve>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})

# Kernel benchmark (make bench; not a test): whole runs and the roofline pieces.
add_executable(bench_kernel ${CMAKE_CURRENT_LIST_DIR}/../bench/bench_kernel.f90)
target_link_libraries(bench_kernel PRIVATE ringlube_kernel)
