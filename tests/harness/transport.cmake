# The runner's transports (harness/transport): in-process, a serial port over a
# pty served by serve(), TCP against serve_tcp(), and the timing helpers, in
# transport_tests; the libserialport backend on a pty (LD_PRELOAD shim
# tests/support/ptyshim.c, built by line.cmake) in transport_libserialport_tests,
# the same source built with SABUS_TRANSPORT_TESTS_UNDER_PTYSHIM.
find_package(Threads REQUIRED)

sabus_add_test(transport_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/harness/transport_test.cpp)
target_link_libraries(transport_tests PRIVATE sabus::transport Threads::Threads)

if(TARGET ptyshim)
  add_executable(transport_libserialport_tests ${CMAKE_CURRENT_SOURCE_DIR}/harness/transport_test.cpp)
  target_compile_definitions(transport_libserialport_tests PRIVATE SABUS_TRANSPORT_TESTS_UNDER_PTYSHIM)
  target_link_libraries(transport_libserialport_tests PRIVATE sabus::transport GTest::gtest GTest::gtest_main
                        Threads::Threads)
  add_dependencies(transport_libserialport_tests ptyshim)
  add_test(NAME harness.transport.libserialport_over_pty COMMAND transport_libserialport_tests)
  set_tests_properties(harness.transport.libserialport_over_pty PROPERTIES
    LABELS integration TIMEOUT 120 ENVIRONMENT "LD_PRELOAD=$<TARGET_FILE:ptyshim>")
  if(SABUS_SANITIZE)
    # As for line_libserialport_tests (line.cmake): the shim is preloaded
    # before the ASan runtime.
    set_tests_properties(harness.transport.libserialport_over_pty PROPERTIES
      ENVIRONMENT_MODIFICATION "ASAN_OPTIONS=string_append::verify_asan_link_order=0")
  endif()
endif()
