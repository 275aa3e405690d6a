#include <relief/core/parallel.h>

#include <tbb/info.h>

namespace relief {

ThreadLimit::ThreadLimit(int threads) {
    if (threads > 0)
        m_control = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, size_t(threads));
}

int ThreadLimit::current() {
    return int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace relief
