# The layering of core/ (docs/architecture.md, "Layers"): a file of a
# subsystem folder includes headers of its own folder and of folders in
# lower layers only; no file of core includes Lua or the binding; a
# planner's internal.h (core/planning/edge_finish/internal.h) is included
# only by its own folder and the planner's .cpp beside it; OpenCASCADE
# headers only by core/cad's .cpp files.
# Run by ctest as CoreLayers:
#   cmake -DROOT=<source dir> -P tests/layers/check_core_layers.cmake
# A new folder under core/ needs a layer here and in the doc.
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<source dir> -P check_core_layers.cmake")
endif()

# folder:layer, lowest first; folders of one layer do not include each other.
set(layers
    common:0
    geometry:1
    tools:2 io:2 cad:2
    parts:3 collision:3 sim:3 toolpath:3
    repair:4 analysis:4 stock:4
    planning:5
    machine:6)
foreach(entry IN LISTS layers)
  string(REPLACE ":" ";" pair "${entry}")
  list(GET pair 0 folder)
  list(GET pair 1 layer)
  set(layer_of_${folder} ${layer})
endforeach()

# What a folder may include, for the message.
function(allowed_for folder out)
  set(names "")
  foreach(entry IN LISTS layers)
    string(REPLACE ":" ";" pair "${entry}")
    list(GET pair 0 other)
    list(GET pair 1 layer)
    if(layer LESS layer_of_${folder} OR other STREQUAL folder)
      list(APPEND names ${other})
    endif()
  endforeach()
  string(REPLACE ";" ", " names "${names}")
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/core/*.h ${ROOT}/core/*.cpp)
list(SORT files)
set(problems "")
set(checked 0)
foreach(file IN LISTS files)
  string(REGEX MATCH "^core/([a-z_]+)/" _ "${file}")
  set(folder ${CMAKE_MATCH_1})
  if(NOT folder)
    continue()  # core/CMakeLists.txt and the like
  endif()
  if(NOT DEFINED layer_of_${folder})
    list(APPEND problems "${file}: core/${folder} has no layer (tests/layers/check_core_layers.cmake, docs/architecture.md)")
    continue()
  endif()
  file(STRINGS ${ROOT}/${file} includes REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]")
  foreach(line IN LISTS includes)
    math(EXPR checked "${checked} + 1")
    if(line MATCHES "[\"<](lua_api/|lua\\.h|lauxlib\\.h|lualib\\.h|lua\\.hpp)")
      list(APPEND problems "${file}: ${line}: core never includes Lua or the binding")
      continue()
    endif()
    # OpenCASCADE headers (*.hxx) are heavy and stay in core/cad's .cpp
    # files: no header of any folder and no other folder sees them.
    if(line MATCHES "[\"<][A-Za-z0-9_]+\\.hxx[\">]" AND NOT file MATCHES "^core/cad/.*\\.cpp$")
      list(APPEND problems "${file}: ${line}: OpenCASCADE is included only by core/cad/*.cpp")
      continue()
    endif()
    if(NOT line MATCHES "\"core/([a-z_]+)/")
      continue()
    endif()
    set(target ${CMAKE_MATCH_1})
    if(line MATCHES "\"(core/[a-z_/]+)/internal\\.h\"")
      set(owner ${CMAKE_MATCH_1})
      string(FIND "${file}" "${owner}/" in_folder)
      if(NOT in_folder EQUAL 0 AND NOT file STREQUAL "${owner}.cpp")
        list(APPEND problems "${file}: ${line}: ${owner}/internal.h is for ${owner}/ and ${owner}.cpp only")
      endif()
    endif()
    if(target STREQUAL folder)
      continue()
    endif()
    if(NOT DEFINED layer_of_${target})
      list(APPEND problems "${file}: ${line}: core/${target} has no layer")
    elseif(NOT layer_of_${target} LESS layer_of_${folder})
      allowed_for(${folder} allowed)
      list(APPEND problems "${file}: ${line}: core/${folder} may include only ${allowed}")
    endif()
  endforeach()
endforeach()

if(problems)
  string(REPLACE ";" "\n  " text "${problems}")
  message(FATAL_ERROR "core layering broken (docs/architecture.md, \"Layers\"):\n  ${text}")
endif()
list(LENGTH files count)
message(STATUS "core layering: ${count} files, ${checked} includes, all one way")
