# The floors of cpp/, checked from the code's own includes, and tests/ mirroring cpp/.
# A quoted include "folder/file.hpp" names the folder it comes from (cpp/ is the include root).
# The floors, bottom up: common; the numerics (linalg, ode, lcp); the engine (mech, then
# modelfile); the case layer (sim); the applications; the command line (cli). A folder may
# include itself and the floors below it. Every folder of cpp/ that is not named here is an
# application: it may include everything up to the case layer and itself, not another
# application, and its cli/ subfolder (its commands, compiled into the executable) stands on
# the command line's floor. The one application built on another is the sieve's incline study
# (cpp/sieve/incline, its own library on the generic sweep of the studies). The Python module
# (python) is a top floor beside the command line: it may include the case layer and every
# application, and nothing includes it.
# Run: cmake -DSOURCE_DIR=<repo> -P tests/layout/check_floors.cmake
cmake_minimum_required(VERSION 3.22)
set(numerics common linalg ode lcp)
set(allowed_common    common)
set(allowed_linalg    common linalg)
set(allowed_ode       common ode)
set(allowed_lcp       common lcp)
set(allowed_mech      ${numerics} mech)
set(allowed_modelfile ${numerics} mech modelfile)
set(allowed_sim       ${numerics} mech modelfile sim)
set(below_applications ${allowed_sim})
set(lower_floors common linalg ode lcp mech modelfile sim cli python)

file(GLOB folders LIST_DIRECTORIES true RELATIVE "${SOURCE_DIR}/cpp" "${SOURCE_DIR}/cpp/*")
set(applications "")
foreach(folder IN LISTS folders)
  if(IS_DIRECTORY "${SOURCE_DIR}/cpp/${folder}" AND NOT folder IN_LIST lower_floors)
    list(APPEND applications ${folder})
  endif()
endforeach()
foreach(app IN LISTS applications)
  set(allowed_${app} ${below_applications} ${app})
endforeach()
set(allowed_cli ${below_applications} ${applications} cli)
set(allowed_python ${below_applications} ${applications} python)
set(allowed_sieve/incline ${below_applications} sieve study)

set(failures "")
foreach(folder IN LISTS folders)
  if(NOT IS_DIRECTORY "${SOURCE_DIR}/cpp/${folder}")
    continue()
  endif()
  file(GLOB_RECURSE files "${SOURCE_DIR}/cpp/${folder}/*.cpp" "${SOURCE_DIR}/cpp/${folder}/*.hpp"
                          "${SOURCE_DIR}/cpp/${folder}/*.h" "${SOURCE_DIR}/cpp/${folder}/*.c")
  foreach(f IN LISTS files)
    file(RELATIVE_PATH rel "${SOURCE_DIR}/cpp" "${f}")
    # The room of a file: its folder; an application's commands (cli/) are the command line's.
    set(room "${folder}")
    if(rel MATCHES "^${folder}/cli/")
      set(room cli)
    elseif(rel MATCHES "^sieve/incline/")
      set(room sieve/incline)
    endif()
    file(STRINGS "${f}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[A-Za-z0-9_]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"([A-Za-z0-9_]+)/.*$" "\\1" target "${line}")
      if(NOT IS_DIRECTORY "${SOURCE_DIR}/cpp/${target}" OR target STREQUAL folder)
        continue()  # its own folder, or a subfolder of it ("detail/...", "contacts/...")
      endif()
      list(FIND allowed_${room} "${target}" at)
      if(at EQUAL -1)
        string(APPEND failures "cpp/${rel}: includes \"${target}/...\": on its floor (${room}) only ${allowed_${room}}\n")
      endif()
    endforeach()
  endforeach()
endforeach()

# The tests mirror the source tree: every tests/<folder> tests cpp/<folder>, or is one of the
# folders that test across it.
set(across cli cases fuzz layout support)
file(GLOB test_folders LIST_DIRECTORIES true RELATIVE "${SOURCE_DIR}/tests" "${SOURCE_DIR}/tests/*")
foreach(folder IN LISTS test_folders)
  if(IS_DIRECTORY "${SOURCE_DIR}/tests/${folder}" AND NOT IS_DIRECTORY "${SOURCE_DIR}/cpp/${folder}")
    list(FIND across "${folder}" at)
    if(at EQUAL -1)
      string(APPEND failures "tests/${folder}/ mirrors no cpp/${folder}/ (and is not one of ${across})\n")
    endif()
  endif()
endforeach()

if(failures)
  message(FATAL_ERROR "the layout is broken:\n${failures}")
endif()
message(STATUS "every include of cpp/ respects the floors; tests/ mirrors cpp/")
