# ctest suite of the Fortran kernel (included from the root CMakeLists.txt).
add_library(ringlube_check STATIC ${CMAKE_CURRENT_LIST_DIR}/check.f90)
target_link_libraries(ringlube_check PUBLIC ringlube_kernel)

foreach(t tridiag tridiag_fixed greenwood_tripp physics_basics reynolds cycle liner jfo time_order
    mixed_share film_viscosity)
  add_executable(test_${t} ${CMAKE_CURRENT_LIST_DIR}/test_${t}.f90)
  target_link_libraries(test_${t} PRIVATE ringlube_check ringlube_io ${LAPACK_LIBRARIES})
  add_test(NAME ${t} COMMAND test_${t} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
endforeach()

# the independent Elrod relaxation used by test_jfo and by the (not run) benchmark bench_jfo
add_library(ringlube_jfo_reference STATIC ${CMAKE_CURRENT_LIST_DIR}/jfo_reference.f90)
target_link_libraries(ringlube_jfo_reference PUBLIC ringlube_kernel)
target_link_libraries(test_jfo PRIVATE ringlube_jfo_reference)
add_executable(bench_jfo ${CMAKE_CURRENT_LIST_DIR}/../bench/bench_jfo.f90)
target_link_libraries(bench_jfo PRIVATE ringlube_jfo_reference)

add_test(NAME bad_decks
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../cli/bad_decks.sh $<TARGET_FILE:ringlube-solve>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME solve_shipped_deck
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../cli/solve_deck.sh $<TARGET_FILE:ringlube-solve>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME concurrent_output
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../cli/concurrent_output.sh $<TARGET_FILE:ringlube-solve>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_executable(test_hdf5_output ${CMAKE_CURRENT_LIST_DIR}/test_hdf5_output.f90)
target_link_libraries(test_hdf5_output PRIVATE ringlube_check ringlube_io)
add_test(NAME hdf5_output COMMAND test_hdf5_output WORKING_DIRECTORY ${CMAKE_BINARY_DIR})
# SIGTERM while a temporary file exists: the program ends by the signal, the file is gone
add_test(NAME temp_removed_on_signal
  COMMAND bash -c "t=$(mktemp -d) && n=$($<TARGET_FILE:test_hdf5_output> signal $t/out.h5); rc=$?; echo \"exit $rc, temporary $n\"; [ $rc -eq 143 ] && [ -n \"$n\" ] && [ ! -e \"$n\" ] && [ -z \"$(ls -A $t)\" ] && rmdir $t")

# Kernel benchmark (make bench; not a test): whole runs and the roofline pieces.
add_executable(bench_kernel ${CMAKE_CURRENT_LIST_DIR}/../bench/bench_kernel.f90)
target_link_libraries(bench_kernel PRIVATE ringlube_kernel)
