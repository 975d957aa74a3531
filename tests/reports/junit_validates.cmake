# Writes the JUnit XML of a run with failures, a known issue and skips, and
# validates it with xmllint against reports/junit.xsd; also checks that the
# schema rejects a file without the attributes Jenkins requires.
if(NOT XMLLINT)
  message(FATAL_ERROR "xmllint not found: install libxml2-utils (tools/install-deps.sh)")
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/known.txt "3.2-status-track-byte: short status reply\n")
execute_process(COMMAND ${SABUS} run --sim --fault short-status --known-issues ${WORK}/known.txt
                        --exclude framing-* --junit ${WORK}/junit.xml --json ${WORK}/run.json
                OUTPUT_QUIET ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "sabus run exited ${rc}, expected 1")
endif()
file(READ ${WORK}/junit.xml xml)
foreach(want "<failure " "<skipped " "<testsuite name=\"§3.2\"")
  string(FIND "${xml}" "${want}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "junit.xml has no ${want}")
  endif()
endforeach()
execute_process(COMMAND ${XMLLINT} --noout --schema ${XSD} ${WORK}/junit.xml RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "junit.xml does not validate:\n${err}")
endif()
# Regenerated from the JSON, it validates too.
execute_process(COMMAND ${SABUS} report ${WORK}/run.json --junit ${WORK}/again.xml OUTPUT_QUIET RESULT_VARIABLE rc)
execute_process(COMMAND ${XMLLINT} --noout --schema ${XSD} ${WORK}/again.xml RESULT_VARIABLE rc2 ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT rc2 EQUAL 0)
  message(FATAL_ERROR "sabus report --junit: ${rc}, validation ${rc2}:\n${err}")
endif()
# The schema is not a rubber stamp: a testsuite without `errors` is refused.
string(REPLACE " errors=\"0\" skipped" " skipped" broken "${xml}")
file(WRITE ${WORK}/broken.xml "${broken}")
execute_process(COMMAND ${XMLLINT} --noout --schema ${XSD} ${WORK}/broken.xml RESULT_VARIABLE rc ERROR_QUIET)
if(rc EQUAL 0)
  message(FATAL_ERROR "the schema accepted a testsuite without errors=")
endif()
