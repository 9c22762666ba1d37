# Reads cmake/layers.txt (the layering table: folder, then the folders it may
# use) into PW_LAYERS (the folders, in order) and PW_LAYER_USES_<folder>.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/layers.txt _pw_rows REGEX "^[a-z]")
set(PW_LAYERS)
foreach(_pw_row IN LISTS _pw_rows)
  string(REGEX REPLACE "[ \t]+" ";" _pw_words "${_pw_row}")
  list(POP_FRONT _pw_words _pw_folder)
  list(REMOVE_ITEM _pw_words "-")
  list(APPEND PW_LAYERS ${_pw_folder})
  set(PW_LAYER_USES_${_pw_folder} ${_pw_words})
endforeach()

# pw_link_layer(<target> <folder>): links <target> to pw::<f> for every folder
# <f> that <folder> may use (PUBLIC for libraries, INTERFACE for header-only
# ones, PRIVATE for executables).
function(pw_link_layer target folder)
  if(NOT folder IN_LIST PW_LAYERS)
    message(FATAL_ERROR "cmake/layers.txt has no row for '${folder}'")
  endif()
  set(deps)
  foreach(f IN LISTS PW_LAYER_USES_${folder})
    list(APPEND deps pw::${f})
  endforeach()
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    target_link_libraries(${target} INTERFACE ${deps})
  elseif(type STREQUAL "EXECUTABLE")
    target_link_libraries(${target} PRIVATE ${deps})
  else()
    target_link_libraries(${target} PUBLIC ${deps})
  endif()
endfunction()
