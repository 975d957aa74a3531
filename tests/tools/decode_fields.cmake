# `sabus decode` decodes the manual's status reply field by field.
execute_process(COMMAND ${SABUS} decode --side both ${EXAMPLES}
                OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit ${rc}, expected 0\n${out}")
endif()
foreach(expected
    "byte 36       az status              0x57           fast, remotely commanded auto move in progress"
    "bytes 14-19   azimuth                \"-152.5\"       -152.5 deg"
    "byte 35       pol equipment          0x58           single port rotating feed, pol movement allowed, 'H' displayed"
    "byte 45       current mode           0x32           REMOTE_MODE"
    "byte 48       exit status            0x38           LOCATE_FUNCTION_COMPLETED"
    "bytes 4-13    sat name               \"SBS 6     \"   \"SBS 6\""
    "byte 3        offline                0x46           'F': remote control disabled"
    "17 frame(s), 0 discarded run(s)")
  string(FIND "${out}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "missing in the output: ${expected}\n--- output ---\n${out}")
  endif()
endforeach()
