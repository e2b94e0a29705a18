# Map loader vs map_server fixtures and bad input (included from CMakeLists.txt).
# Fixtures: tests/core/map_server_reference.py and tests/core/make_bad_fixtures.py.
gather_add_gtest(test_core_loader SOURCES map_loader_test.cpp bad_input_test.cpp LIBS gather_core)
if(NOT GATHER_CATKIN)
  # catkin mode runs tests/cli/bad_input.sh from the Makefile instead.
  add_test(NAME cli_bad_input COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/../cli/bad_input.sh "$<TARGET_FILE:gather> info")
endif()
