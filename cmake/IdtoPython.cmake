# The Python module (python/): pybind11 from Debian, built for Debian's /usr/bin/python3 by
# default, whatever python3 comes first on PATH (set Python_EXECUTABLE to choose another).
# Sets IDTO_PYTHON_AVAILABLE when pybind11, the interpreter's development files and numpy are
# found; IDTO_BUILD_PYTHON defaults to it.
if(NOT Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python interpreter of the idto module")
endif()
set(IDTO_PYTHON_AVAILABLE OFF)
if(NOT DEFINED IDTO_BUILD_PYTHON OR IDTO_BUILD_PYTHON)
  find_package(Python 3.8 QUIET COMPONENTS Interpreter Development.Module)
  if(Python_FOUND)
    # pybind11 uses the interpreter found above (its FindPython mode).
    find_package(pybind11 2.6 CONFIG QUIET)
    execute_process(COMMAND ${Python_EXECUTABLE} -c "import numpy"
                    RESULT_VARIABLE _idto_numpy OUTPUT_QUIET ERROR_QUIET)
    if(pybind11_FOUND AND _idto_numpy EQUAL 0)
      set(IDTO_PYTHON_AVAILABLE ON)
    endif()
  endif()
endif()
