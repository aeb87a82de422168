// sightline-cli pvs bake --mpi: the ranks share the cells (cell c to rank c % size, as --shard),
// every rank bakes its own from its own scene load, and rank 0 gathers the rows and writes the
// outputs. Each cell's row depends only on the inputs (PvsBake.h), so the file is byte-identical
// to a one-process bake's. Built only where CMake found MPI (Open MPI from Debian).

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include <mpi.h>

#include "cli/PvsBakeJob.h"
#include "base/Error.h"
#include "visibility/pvs/PvsFile.h"

namespace sightline::cli {

bool pvsHasMpi() { return true; }

namespace {

/// Whether every rank got here without an error (a rank that failed says so; none blocks).
bool allOk(bool ok)
{
    int mine = ok ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all == 1;
}

} // namespace

int runMpiBake(const PvsBakeArgs& args, int argc, char** argv)
{
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised)
        MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const auto start = std::chrono::steady_clock::now();
    std::string error;
    std::optional<PvsBakeJob> job;
    pvs::VisibilityRows rows, cellRows;
    pvs::PvsStats stats;
    std::vector<std::size_t> cells;
    try {
        job.emplace(prepareBakeJob(args));
        cells = pvs::shardCells(job->data.cells.size(), std::uint32_t(rank), std::uint32_t(size));
        rows = cells.empty() ? pvs::VisibilityRows(job->data.cells.size(), job->data.objects.size())
                             : job->baker->bake(cells, {}, &stats);
        if (job->baker->settings().cellRows)
            cellRows = cells.empty() ? pvs::VisibilityRows(job->data.cells.size(), job->data.cells.size())
                                     : job->baker->bakeCellRows(cells, {}, &stats);
    } catch (const std::exception& e) {
        error = describeFailure(e, "baking on rank " + std::to_string(rank));
    }
    if (!allOk(error.empty())) {
        if (!error.empty())
            std::cerr << "sightline-cli: error: " << (size > 1 ? "rank " + std::to_string(rank) + ": " : "") << error << "\n";
        MPI_Finalize();
        return 1;
    }
    // Every rank packs its rows (cell order; each cell's object row, then its cell row when baked),
    // rank 0 gathers them.
    const std::size_t rowBytes = rows.rowBytes(), cellRowBytes = cellRows.cellCount() ? cellRows.rowBytes() : 0;
    std::vector<std::uint8_t> mine;
    for (std::size_t c : cells) {
        mine.insert(mine.end(), rows.row(c), rows.row(c) + rowBytes);
        if (cellRowBytes)
            mine.insert(mine.end(), cellRows.row(c), cellRows.row(c) + cellRowBytes);
    }
    const int count = int(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size), 0), displacements(static_cast<std::size_t>(size), 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<std::uint8_t> all;
    if (rank == 0) {
        int total = 0;
        for (int r = 0; r < size; ++r) {
            displacements[std::size_t(r)] = total;
            total += counts[std::size_t(r)];
        }
        all.resize(std::size_t(total));
    }
    MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), displacements.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    double slowest = stats.coarseMs + stats.refineMs + stats.cellRowsMs, bakeMs = 0.0;
    MPI_Reduce(&slowest, &bakeMs, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    int code = 0;
    if (rank == 0) {
        try {
            pvs::PvsData data = job->data;
            data.rows = pvs::VisibilityRows(data.cells.size(), data.objects.size());
            if (cellRowBytes)
                data.cellRows = pvs::VisibilityRows(data.cells.size(), data.cells.size());
            const std::size_t stride = rowBytes + cellRowBytes;
            for (int r = 0; r < size; ++r) {
                const auto its = pvs::shardCells(data.cells.size(), std::uint32_t(r), std::uint32_t(size));
                const std::uint8_t* p = all.data() + displacements[std::size_t(r)];
                for (std::size_t k = 0; k < its.size(); ++k) {
                    std::copy(p + k * stride, p + k * stride + rowBytes, data.rows.row(its[k]));
                    if (cellRowBytes)
                        std::copy(p + k * stride + rowBytes, p + (k + 1) * stride, data.cellRows.row(its[k]));
                }
            }
            applyPvsOverrides(job->overrides, data.rows);
            const auto sizes = writePvsOutputs(data, args.outputs);
            std::optional<pvs::AccuracyReport> accuracy;
            if (args.check)
                accuracy = checkBake(*job, data, args.threads);
            printBakeSummary(*job, data, stats, bakeMs, size, sizes, accuracy ? &*accuracy : nullptr, args);
        } catch (const std::exception& e) {
            std::cerr << "sightline-cli: error: " << describeFailure(e, "writing the PVS") << "\n";
            code = 1;
        }
    }
    (void)start;
    MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Finalize();
    return code;
}

} // namespace sightline::cli
