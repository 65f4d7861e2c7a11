// cli/heap_settings.hpp — how the program's heap keeps memory it frees.
#pragma once

namespace nearcap::cli {

// Keep freed memory in the process for the next allocation of its size;
// `nearcap sweep` calls it before its first configuration.
//
// A sweep allocates and frees buffers of megabytes for every draw and frame
// (a mesh's clip-space vertices and set-up triangles, the exact reference's
// grids).  glibc's defaults give a block above its mmap threshold (128 KiB,
// raised only as far as the largest block freed so far) pages of its own,
// returned to the kernel when freed, and return free memory above 128 KiB at
// the heap's top: the next frame's buffer of the same size then faults in
// fresh, zeroed pages, a kernel entry per page.  Here blocks up to glibc's
// largest threshold (32 MiB) come from the heap, and the heap is not trimmed,
// so a process holds its peak heap until it exits.  Nothing elsewhere (a
// library's allocations, their results) depends on this; without glibc it
// does nothing.
void keep_freed_memory();

}  // namespace nearcap::cli
