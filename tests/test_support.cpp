// Shared test helpers live here when more than one test file needs them.
// (Created on the tools branch because tests/CMakeLists.txt lists this file;
// the collision tests keep their meshes in tests/collision/test_meshes.h.)
