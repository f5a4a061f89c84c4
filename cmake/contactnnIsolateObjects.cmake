# Run as a script (cmake -P) by lib/search/CMakeLists.txt: the objects of one kernel variant, compiled for one
# instruction set, made to share no symbol with the rest of the program. Every symbol they define gets the
# suffix .TAG (a clone suffix, which demanglers show as "[clone .isa_avx2]"), in every one of them (the variant's
# objects still resolve among themselves), except the variant's entry points, whose names hold TAG already
# (namespace contactnn::search::detail::TAG, isa_dispatch.hpp).
#
# Why: an inline function or a template instantiated in a kernel file (BilinearBlock<32>::build, a std:: or
# Eigen helper not inlined) is a weak symbol, and the linker keeps one copy of each weak symbol for the whole
# library: the AVX-512 variant's copy could serve the baseline variant, or code outside the kernels, and stop a
# CPU without AVX-512 with SIGILL. Renamed, each variant keeps its own copies, and no other code can bind to
# them. (A mutable static local of such an inline function would be one per variant: the kernels have none.)
#
#   -DNM=nm -DOBJCOPY=objcopy -DTAG=isa_avx2 -DINPUTS=dir/a.cpp.o|dir/b.cpp.o -DOUTDIR=out
# writes out/a.o, out/b.o and out/renamed-symbols.txt (the renaming, "old new" per line).
cmake_minimum_required(VERSION 3.25)
foreach(var NM OBJCOPY TAG INPUTS OUTDIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "contactnnIsolateObjects.cmake: -D${var}=... is required")
  endif()
endforeach()
string(REPLACE "|" ";" inputs "${INPUTS}")
set(MAP "${OUTDIR}/renamed-symbols.txt")
file(MAKE_DIRECTORY "${OUTDIR}")

# Every symbol defined in any of the objects (nm -P: "name type value size"), local ones too, so that the
# disassembly names each function of the variant with its tag.
set(names "")
foreach(object IN LISTS inputs)
  execute_process(COMMAND "${NM}" --defined-only -P "${object}" OUTPUT_VARIABLE text RESULT_VARIABLE rc
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} --defined-only -P ${object} failed (${rc}): ${err}")
  endif()
  string(REGEX MATCHALL "[^\n]+" lines "${text}")
  foreach(line IN LISTS lines)
    if(line MATCHES "^([^ ]+) ([A-Za-z]) ")
      set(name "${CMAKE_MATCH_1}")
      set(type "${CMAKE_MATCH_2}")
      # Absolute symbols (a) are no code; a name with TAG is an entry point; a renamed name is not renamed again.
      if(NOT type MATCHES "^[aA]$" AND NOT name MATCHES "${TAG}")
        list(APPEND names "${name}")
      endif()
    endif()
  endforeach()
endforeach()
list(REMOVE_DUPLICATES names)
set(map "")
foreach(name IN LISTS names)
  string(APPEND map "${name} ${name}.${TAG}\n")
endforeach()
file(WRITE "${MAP}" "${map}")

foreach(input IN LISTS inputs)
  get_filename_component(stem "${input}" NAME_WE)  # kernels_single.cpp.o -> kernels_single
  set(output "${OUTDIR}/${stem}.o")
  execute_process(COMMAND "${OBJCOPY}" "--redefine-syms=${MAP}" "${input}" "${output}" RESULT_VARIABLE rc
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${OBJCOPY} --redefine-syms=${MAP} ${input} ${output} failed (${rc}): ${err}")
  endif()
endforeach()
