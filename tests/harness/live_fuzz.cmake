# The live fuzzer (harness/live_fuzz): its parts in live_fuzz_tests; `sabus
# fuzz` as a process, finding injected faults, in live_fuzz_cli_tests.
sabus_add_test(live_fuzz_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/live_fuzz_test.cpp)
target_link_libraries(live_fuzz_tests PRIVATE sabus::live_fuzz sabus::vectors)

sabus_add_test(live_fuzz_cli_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/live_fuzz_cli_test.cpp)
target_compile_definitions(live_fuzz_cli_tests PRIVATE SABUS_BIN="$<TARGET_FILE:sabus>")
add_dependencies(live_fuzz_cli_tests sabus)
