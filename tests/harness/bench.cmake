# The bench workflow: `sabus proxy`, `sabus record`, `sabus decode` of captures.
sabus_add_test(bench_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/bench_test.cpp)
target_link_libraries(bench_tests PRIVATE sabus::line sabus::bench nlohmann_json::nlohmann_json)
target_compile_definitions(bench_tests PRIVATE SABUS_BIN="$<TARGET_FILE:sabus>" SABUS_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_include_directories(bench_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
add_dependencies(bench_tests sabus)
