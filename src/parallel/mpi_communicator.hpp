#pragma once
// The MPI communicator's factory (src/parallel/mpi_communicator.cpp, compiled
// only with BRIDGEFIT_MPI; BRIDGEFIT_HAVE_MPI is defined then).
#include <memory>

#include "bridgefit/parallel/communicator.hpp"

namespace bridgefit::parallel {
#ifdef BRIDGEFIT_HAVE_MPI
// MPI_COMM_WORLD (MPI initialised with MPI_THREAD_FUNNELED: only the thread
// that made the communicator calls MPI; errors returned, not fatal).
std::unique_ptr<Communicator> MakeMpiWorldCommunicator();
#endif
}  // namespace bridgefit::parallel
