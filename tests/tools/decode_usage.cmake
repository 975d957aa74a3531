# Bad usage exits 2 with a message, never 0 or 1.
foreach(args "decode" "decode;--hex;0g" "decode;--side;sideways;--hex;02" "decode;--address;200;--hex;02" "nosuchcommand")
  execute_process(COMMAND ${SABUS} ${args} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "sabus ${args}: exit ${rc}, expected 2\n${out}${err}")
  endif()
endforeach()
