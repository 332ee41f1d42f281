# ctest tradeoffs_quick: runs `idto-tradeoffs --quick --out OUT` and checks that it exits 0 and
# writes OUT/tradeoffs.md with the summary section. -DPROGRAM=... -DOUT=...
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${CMAKE_COMMAND} -E env OMP_WAIT_POLICY=passive ${PROGRAM} --quick
                        --out ${OUT}
                RESULT_VARIABLE exit_code)
if(NOT exit_code EQUAL 0)
  message(FATAL_ERROR "idto-tradeoffs --quick exited with ${exit_code}")
endif()
if(NOT EXISTS ${OUT}/tradeoffs.md)
  message(FATAL_ERROR "idto-tradeoffs --quick did not write ${OUT}/tradeoffs.md")
endif()
file(READ ${OUT}/tradeoffs.md text)
string(FIND "${text}" "Summary: which knob buys the most speed" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${OUT}/tradeoffs.md has no summary section")
endif()
