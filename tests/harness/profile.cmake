# Device profiles: the YAML loader, its errors, the writer and the shipped
# profiles (vectors/profiles/). Included from tests/CMakeLists.txt.
sabus_add_test(profile_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/profile_test.cpp)
target_link_libraries(profile_tests PRIVATE sabus::profile)
