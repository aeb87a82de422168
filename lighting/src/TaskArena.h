#pragma once
// Internal to the lighting library: runs work in a TBB arena of a given size.

#include <tbb/task_arena.h>

namespace sightline {

/// Runs `body` in an arena of `threads` worker threads (0: the default arena, all cores).
template <typename Body>
void inArena(int threads, Body&& body)
{
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute(body);
    } else {
        body();
    }
}

} // namespace sightline
