# sabus_library(NAME [HEADERS_ONLY] [SOURCES src...] [PUBLIC dep...] [PRIVATE dep...])
# One folder is one library is one target (harness/README.md): sabus_NAME,
# also named sabus::NAME, with the folder's include/ as its public headers.
# HEADERS_ONLY: an interface library (no sources; PUBLIC are its
# dependencies, PRIVATE is not allowed).
function(sabus_library name)
  cmake_parse_arguments(L "HEADERS_ONLY" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  set(target sabus_${name})
  set(headers $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
  if(L_HEADERS_ONLY)
    if(L_SOURCES OR L_PRIVATE)
      message(FATAL_ERROR "sabus_library(${name} HEADERS_ONLY): no SOURCES or PRIVATE")
    endif()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${headers})
    target_link_libraries(${target} INTERFACE ${L_PUBLIC})
  else()
    add_library(${target} ${L_SOURCES})
    target_include_directories(${target} PUBLIC ${headers})
    target_compile_features(${target} PUBLIC cxx_std_20)
    target_link_libraries(${target} PUBLIC ${L_PUBLIC} PRIVATE ${L_PRIVATE})
  endif()
  add_library(sabus::${name} ALIAS ${target})
endfunction()
