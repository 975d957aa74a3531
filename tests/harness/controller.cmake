sabus_add_test(controller_tests unit ${CMAKE_CURRENT_SOURCE_DIR}/harness/controller_test.cpp)
target_link_libraries(controller_tests PRIVATE sabus::controller sabus::profile)
sabus_add_test(controller_properties property ${CMAKE_CURRENT_SOURCE_DIR}/harness/controller_properties.cpp)
target_link_libraries(controller_properties PRIVATE sabus::controller)
