# Unity builds that a second checkout can take from ccache.
#
# A unity batch is a generated file that #includes eight of a target's sources, so the headers they
# share are parsed once. CMake 3.25 writes its batches with absolute paths, and ccache hashes what a
# file says: a clone in another folder gets other batch files and misses the cache for every object
# (CMake 3.32's UNITY_BUILD_RELOCATABLE is the same fix, not in Debian's CMake). These batches name
# their sources relative to the batch file, so two clones with the same build folder name write the
# same bytes, and ccache (with CCACHE_BASEDIR, Pp5Ccache.cmake) finds the first clone's objects.
#
# pp5_unity_batches(<directory>) batches every target defined under <directory>, after they all exist.
# Sources excluded from batching: generated ones (they may not exist at configure time), ones with
# compile flags of their own, and any with SKIP_UNITY_BUILD_INCLUSION. A target of one source gets a batch of one too: a source two targets of
# a folder share (tests/fuzz/replay_main.cpp) is marked for the folder, not the target, so every
# target that lists it must compile it through a batch.
set(PP5_UNITY_BATCH_SIZE 8 CACHE STRING "Sources per unity batch")

# Written only when the text changes, so a reconfiguration rebuilds no batch.
function(pp5_write_if_changed path content)
  if(EXISTS ${path})
    file(READ ${path} old)
    if(old STREQUAL content)
      return()
    endif()
  endif()
  file(WRITE ${path} "${content}")
endfunction()

function(pp5_batch_target target)
  get_target_property(type ${target} TYPE)
  if(NOT type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|MODULE_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
    return()
  endif()
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  get_target_property(binary_dir ${target} BINARY_DIR)

  # Absolute paths throughout: a relative one would be read from this (the top) folder, not the target's.
  set(batchable)
  foreach(source IN LISTS sources)
    if(NOT source MATCHES "\\.(cpp|cc|cxx)$" OR source MATCHES "^\\$<")
      continue()
    endif()
    cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${source_dir} NORMALIZE)
    get_source_file_property(generated ${source} TARGET_DIRECTORY ${target} GENERATED)
    get_source_file_property(skip ${source} TARGET_DIRECTORY ${target} SKIP_UNITY_BUILD_INCLUSION)
    get_source_file_property(header_only ${source} TARGET_DIRECTORY ${target} HEADER_FILE_ONLY)
    get_source_file_property(batched ${source} TARGET_DIRECTORY ${target} PP5_IN_UNITY_BATCH)
    if(generated OR skip OR (header_only AND NOT batched))
      continue()
    endif()
    # A source with flags of its own (a data folder's path defined for it alone) compiles by itself.
    set(own_flags FALSE)
    foreach(property COMPILE_DEFINITIONS COMPILE_OPTIONS COMPILE_FLAGS INCLUDE_DIRECTORIES)
      get_source_file_property(value ${source} TARGET_DIRECTORY ${target} ${property})
      if(value)
        set(own_flags TRUE)
      endif()
    endforeach()
    if(own_flags)
      continue()
    endif()
    list(APPEND batchable ${source})
  endforeach()
  list(LENGTH batchable count)
  if(count EQUAL 0)
    return()
  endif()

  # Batches of PP5_UNITY_BATCH_SIZE sources in the target's order, the last one possibly smaller.
  set(batch_dir ${binary_dir}/unity_batches)
  set(batches)
  math(EXPR last_index "${count} - 1")
  foreach(index RANGE 0 ${last_index} ${PP5_UNITY_BATCH_SIZE})
    list(SUBLIST batchable ${index} ${PP5_UNITY_BATCH_SIZE} members)
    set(content "// Unity batch of ${target} (cmake/Pp5UnityBuild.cmake)\n")
    foreach(source IN LISTS members)
      file(RELATIVE_PATH relative ${batch_dir} ${source})
      string(APPEND content "#include \"${relative}\"\n")
    endforeach()
    math(EXPR batch_number "${index} / ${PP5_UNITY_BATCH_SIZE}")
    set(batch ${batch_dir}/${target}_${batch_number}.cpp)
    pp5_write_if_changed(${batch} "${content}")
    list(APPEND batches ${batch})
  endforeach()

  # The sources stay in the target (IDEs list them, edits to them rebuild their batch through the
  # compiler's dependency file) but are compiled only through their batch.
  set_source_files_properties(${batchable} TARGET_DIRECTORY ${target} PROPERTIES HEADER_FILE_ONLY ON
                                                                               PP5_IN_UNITY_BATCH ON)
  target_sources(${target} PRIVATE ${batches})
endfunction()

function(pp5_unity_batches directory)
  get_property(targets DIRECTORY ${directory} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    pp5_batch_target(${target})
  endforeach()
  get_property(subdirectories DIRECTORY ${directory} PROPERTY SUBDIRECTORIES)
  foreach(subdirectory IN LISTS subdirectories)
    pp5_unity_batches(${subdirectory})
  endforeach()
endfunction()
