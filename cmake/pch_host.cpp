// Host of a shared precompiled header (see cmake/precompiled_headers.cmake): compiles nothing
// itself; the targets of the project reuse the header it precompiles.
