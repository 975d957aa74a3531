# The runs of issue 21, end to end with the sabus binary: `sabus run --sim
# --fault F --report-dir D` for each fault in FAULTS (a controller that gets
# its framing wrong), then `sabus report D/run.json` writes the JSON, JUnit,
# HTML and Markdown again: each must be the file the run wrote, byte for
# byte; and `sabus diff` reads the run against the clean one (exit 1: it
# regressed), never refusing the file (exit 2).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${SABUS} run --sim --report-dir ${WORK}/clean OUTPUT_QUIET ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sabus run --sim exited ${rc}")
endif()
foreach(fault ${FAULTS})
  set(run ${WORK}/${fault})
  execute_process(COMMAND ${SABUS} run --sim --fault ${fault} --report-dir ${run} OUTPUT_QUIET ERROR_QUIET RESULT_VARIABLE rc)
  if(rc EQUAL 0 OR rc EQUAL 2)
    message(FATAL_ERROR "${fault}: sabus run exited ${rc}, expected a failing run")
  endif()
  execute_process(COMMAND ${SABUS} report ${run}/run.json --json ${run}/again.json --junit ${run}/again.xml
                          --html ${run}/again.html --md ${run}/again.md
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${fault}: sabus report ${run}/run.json exited ${rc}:\n${out}${err}")
  endif()
  foreach(pair "run.json:again.json" "junit.xml:again.xml" "report.html:again.html" "summary.md:again.md")
    string(REPLACE ":" ";" files ${pair})
    list(GET files 0 written)
    list(GET files 1 rebuilt)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${run}/${written} ${run}/${rebuilt} RESULT_VARIABLE differ)
    if(differ)
      message(FATAL_ERROR "${fault}: ${rebuilt}, rebuilt from run.json, is not the ${written} the run wrote")
    endif()
  endforeach()
  execute_process(COMMAND ${SABUS} diff ${WORK}/clean/run.json ${run}/run.json OUTPUT_QUIET ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 1)
    message(FATAL_ERROR "${fault}: sabus diff exited ${rc}, expected 1 (regressed):\n${err}")
  endif()
  message(STATUS "${fault}: run.json, junit.xml, report.html and summary.md rebuilt the same; diff reads it")
endforeach()
