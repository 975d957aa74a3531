# The conformance runner against the in-process reference controller.
sabus_add_test(runner_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/runner_test.cpp)
target_link_libraries(runner_tests PRIVATE sabus::runner sabus::transport sabus::vectors)

# `sabus run` as a process, against `sabus sim` over a pty and TCP.
sabus_add_test(run_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/run_test.cpp)
target_include_directories(run_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(run_tests PRIVATE nlohmann_json::nlohmann_json)
target_compile_definitions(run_tests PRIVATE SABUS_BIN="$<TARGET_FILE:sabus>" SABUS_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_dependencies(run_tests sabus)
