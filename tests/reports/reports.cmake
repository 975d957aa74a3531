# The reports library, `sabus report` and `sabus diff`.
sabus_add_test(reports_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/reports/reports_test.cpp)
target_link_libraries(reports_tests PRIVATE sabus::reports)

sabus_add_test(reports_cli_tests integration ${CMAKE_CURRENT_SOURCE_DIR}/reports/reports_cli_test.cpp)
target_link_libraries(reports_cli_tests PRIVATE nlohmann_json::nlohmann_json)
target_compile_definitions(reports_cli_tests PRIVATE SABUS_BIN="$<TARGET_FILE:sabus>")
add_dependencies(reports_cli_tests sabus)

# The JUnit file of a failing run with a known issue validates against
# reports/junit.xsd (the format Jenkins and GitLab read).
find_program(XMLLINT xmllint)
add_test(NAME reports.junit_validates
         COMMAND ${CMAKE_COMMAND} -DSABUS=$<TARGET_FILE:sabus> -DXMLLINT=${XMLLINT}
                 -DXSD=${PROJECT_SOURCE_DIR}/reports/junit.xsd -DWORK=${CMAKE_CURRENT_BINARY_DIR}/reports-junit
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/reports/junit_validates.cmake)
# The HTML report renders in headless Chromium with its summary in the DOM;
# skipped (exit 77) when /usr/bin/chromium is not installed (README).
add_test(NAME reports.html_renders_in_chromium
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/reports/html_in_chromium.sh $<TARGET_FILE:sabus>
                 ${CMAKE_CURRENT_BINARY_DIR}/reports-html)
set_tests_properties(reports.junit_validates reports.html_renders_in_chromium PROPERTIES LABELS integration)
set_tests_properties(reports.html_renders_in_chromium PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120)
