# vectors/README.md carries `sabus vectors list --summary` between its
# suite-summary markers; fails when the table is not current
# (tools/update-suite-docs.sh rewrites it).
execute_process(COMMAND ${SABUS} vectors list --summary OUTPUT_VARIABLE table RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sabus vectors list --summary exited ${rc}")
endif()
file(READ ${README} readme)
string(FIND "${readme}" "<!-- suite-summary:begin -->\n" begin)
string(FIND "${readme}" "<!-- suite-summary:end -->" end)
if(begin EQUAL -1 OR end EQUAL -1)
  message(FATAL_ERROR "${README} has no suite-summary markers")
endif()
math(EXPR begin "${begin} + 29")
math(EXPR length "${end} - ${begin}")
string(SUBSTRING "${readme}" ${begin} ${length} current)
if(NOT current STREQUAL table)
  message(FATAL_ERROR "${README}: the suite table is not current; run tools/update-suite-docs.sh\nexpected:\n${table}")
endif()
