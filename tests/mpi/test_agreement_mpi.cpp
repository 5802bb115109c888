// MPI agreement tests: see tests/mpi/CMakeLists.txt.
