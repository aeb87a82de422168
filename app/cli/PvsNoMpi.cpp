// sightline-cli pvs bake --mpi where CMake found no MPI: says so, in one line.

#include "cli/PvsBakeJob.h"
#include "base/Error.h"

namespace sightline::cli {

bool pvsHasMpi() { return false; }

int runMpiBake(const PvsBakeArgs&, int, char**)
{
    throw Error("--mpi: this sightline-cli was built without MPI (install libopenmpi-dev openmpi-bin and configure "
                "again), or bake with --shard I/N and 'pvs merge'");
}

} // namespace sightline::cli
