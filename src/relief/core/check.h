#pragma once
// Programmer-error checks. RELIEF_CHECK is always on and aborts with file:line; RELIEF_DCHECK
// compiles away in release builds and is the only kind allowed in per-ray loops.
#include <cstdio>
#include <cstdlib>

#define RELIEF_CHECK(cond)                                                              \
    do {                                                                                \
        if (!(cond)) {                                                                  \
            std::fprintf(stderr, "relief: internal error: check failed at %s:%d: %s\n", \
                         __FILE__, __LINE__, #cond);                                    \
            std::abort();                                                               \
        }                                                                               \
    } while (0)

#ifdef NDEBUG
#define RELIEF_DCHECK(cond) \
    do {                    \
    } while (0)
#else
#define RELIEF_DCHECK(cond) RELIEF_CHECK(cond)
#endif
