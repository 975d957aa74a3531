# Conformance vectors: the loader, its errors, lint, and the shipped files
# (vectors/*.yaml), which also run against the reference controller.
# Included from tests/CMakeLists.txt.
sabus_add_test(vector_loader_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/vector_loader_test.cpp)
target_link_libraries(vector_loader_tests PRIVATE sabus::vectors sabus::controller)

# `sabus vectors lint` on the shipped tree: exit 0, and 1 / 2 on errors / bad
# usage. Needs the command registered in tools/sabus/main.cpp.
set(SABUS_VECTORS_BAD ${CMAKE_CURRENT_BINARY_DIR}/vectors-lint-bad.yaml)
file(WRITE ${SABUS_VECTORS_BAD} "paragraph: \"3.2\"\ntitle: t\nvectors:\n  - id: 3.2-x\n    comment: c\n    level: must\n")
add_test(NAME cli.vectors.lint_shipped COMMAND $<TARGET_FILE:sabus> vectors lint)
add_test(NAME cli.vectors.lint_errors_exit_1
         COMMAND sh -c "\"$0\" vectors lint \"$1\"; test $? -eq 1" $<TARGET_FILE:sabus> ${SABUS_VECTORS_BAD})
add_test(NAME cli.vectors.usage_exits_2
         COMMAND sh -c "\"$0\" vectors lint /no/such/path; test $? -eq 2" $<TARGET_FILE:sabus>)
set_tests_properties(cli.vectors.lint_shipped cli.vectors.lint_errors_exit_1 cli.vectors.usage_exits_2
                     PROPERTIES LABELS integration)

# Every vector's command bytes split at every point give the same receiver events.
sabus_add_test(vector_chunk_properties property ${CMAKE_CURRENT_SOURCE_DIR}/property/vector_chunk_properties.cpp)
target_link_libraries(vector_chunk_properties PRIVATE sabus::vectors sabus::controller sabus::runner sabus::transport)

# The suite's gates: `sabus vectors coverage` has no required cell without a
# vector; every shipped profile passes and every injected fault fails a
# must-level vector (tools/gates/suite_gates.cpp prints the mutation score).
add_test(NAME gate.coverage COMMAND $<TARGET_FILE:sabus> vectors coverage --missing)
set_tests_properties(gate.coverage PROPERTIES LABELS gate)
if(NOT SABUS_SANITIZE)
  # Some 45 runs of the whole suite: minutes under the sanitizers, whose
  # build runs the in-process profile gate (Runner.ShippedVectorsPassOnTheShippedProfiles).
  add_test(NAME gate.suite COMMAND $<TARGET_FILE:suite_gates>)
  set_tests_properties(gate.suite PROPERTIES LABELS gate)
endif()

# The generated parts of the suite's documents are current (tools/update-suite-docs.sh).
add_test(NAME gate.errata_vector_lists COMMAND $<TARGET_FILE:sabus> vectors errata --check ${PROJECT_SOURCE_DIR}/protocol/ERRATA.md)
add_test(NAME gate.suite_summary_current
         COMMAND ${CMAKE_COMMAND} -DSABUS=$<TARGET_FILE:sabus> -DREADME=${PROJECT_SOURCE_DIR}/vectors/README.md
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/cli/suite_summary_current.cmake)
set_tests_properties(gate.errata_vector_lists gate.suite_summary_current PROPERTIES LABELS gate)

sabus_add_test(coverage_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/coverage_test.cpp)
target_link_libraries(coverage_tests PRIVATE sabus::vectors)
