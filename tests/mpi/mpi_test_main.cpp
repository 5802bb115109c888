// Catch2 under MPI: every rank runs the same test cases in the same order (they make
// collective calls); the exit status is the worst over ranks, so a failure on any rank fails
// the CTest entry. Tests keep collectives in step: each rank computes its verdict, the ranks
// agree on it (all_ranks), then every rank asserts the agreed value.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <mpi.h>

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  Catch::Session session;
  int rc = session.applyCommandLine(argc, argv);
  if (rc == 0) rc = session.run();
  int worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
