# `sabus sim` as a process, over a pty and TCP.
sabus_add_test(sim_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/sim_test.cpp)
target_link_libraries(sim_tests PRIVATE sabus::line)
target_compile_definitions(sim_tests PRIVATE SABUS_BIN="$<TARGET_FILE:sabus>")
target_include_directories(sim_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
add_dependencies(sim_tests sabus)
