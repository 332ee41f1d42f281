# ctest tradeoffs_quick: runs `idto-tradeoffs --quick --out OUT` and checks that it exits 0 and
# writes OUT/tradeoffs.md with the summary section and the key strings of the derivative and
# Table 4 studies. -DPROGRAM=... -DOUT=...
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
# The derivative study compares the analytic derivatives with both difference schemes, and the
# Table 4 study counts the cells at or below the paper's for both of its grids.
foreach(expected "Analytic derivatives vs forward and central differences"
                 "analytic: ‖g − g_ref‖ (relative)" "Cells at or below the paper's number")
  string(FIND "${text}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${OUT}/tradeoffs.md lacks \"${expected}\"")
  endif()
endforeach()
