// Robustness tests: see CMakeLists.txt in this folder.
