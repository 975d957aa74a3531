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
