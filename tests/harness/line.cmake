# Line endpoints and the server loop (harness/line): ptys, termios, TCP and
# serve() in line_tests; the libserialport backend on a pty, which needs the
# LD_PRELOAD shim tests/support/ptyshim.c, in line_libserialport_tests (the
# same source built with SABUS_LINE_TESTS_UNDER_PTYSHIM).
find_package(Threads REQUIRED)

sabus_add_test(line_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/line_test.cpp)
target_link_libraries(line_tests PRIVATE sabus::line Threads::Threads)

# The shim is C; the project's warning flags (add_compile_options) apply.
enable_language(C)
add_library(ptyshim SHARED ${CMAKE_CURRENT_SOURCE_DIR}/support/ptyshim.c)
set_target_properties(ptyshim PROPERTIES C_STANDARD 11 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
target_link_libraries(ptyshim PRIVATE ${CMAKE_DL_LIBS})

add_executable(line_libserialport_tests ${CMAKE_CURRENT_SOURCE_DIR}/harness/line_test.cpp)
target_compile_definitions(line_libserialport_tests PRIVATE SABUS_LINE_TESTS_UNDER_PTYSHIM)
target_link_libraries(line_libserialport_tests PRIVATE sabus::line GTest::gtest GTest::gtest_main Threads::Threads)
add_dependencies(line_libserialport_tests ptyshim)
add_test(NAME harness.line.libserialport_over_pty COMMAND line_libserialport_tests)
set_tests_properties(harness.line.libserialport_over_pty PROPERTIES
  LABELS integration TIMEOUT 120 ENVIRONMENT "LD_PRELOAD=$<TARGET_FILE:ptyshim>")
if(SABUS_SANITIZE)
  # With g++ the ASan runtime is a shared library and must come first in the
  # initial library list; the preloaded shim comes before it. The shim only
  # forwards to the next definitions, so skip that check, keeping any
  # ASAN_OPTIONS the caller set (a leading ':' is fine for ASan).
  set_tests_properties(harness.line.libserialport_over_pty PROPERTIES
    ENVIRONMENT_MODIFICATION "ASAN_OPTIONS=string_append::verify_asan_link_order=0")
endif()
