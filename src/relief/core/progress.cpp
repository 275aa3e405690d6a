#include <relief/core/progress.h>

#include <unistd.h>

#include <cstdio>

namespace relief {

namespace {
std::atomic<bool> gQuiet{false};
}

void Progress::setQuiet(bool quiet) { gQuiet = quiet; }

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_enabled(!gQuiet && isatty(STDERR_FILENO)),
      m_start(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
    if (!m_enabled) return;
    draw(m_total);
    std::fputc('\n', stderr);
}

void Progress::advance(int64_t amount) {
    const int64_t done = m_done += amount;
    if (!m_enabled) return;
    const int64_t ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::steady_clock::now() - m_start)
                           .count();
    int64_t last = m_lastDrawMs.load();
    if (ms - last < 100 || !m_lastDrawMs.compare_exchange_strong(last, ms)) return;
    draw(done);
}

void Progress::draw(int64_t done) {
    const double fraction = double(done) / double(m_total);
    const int width = 30;
    const int filled = int(fraction * width + 0.5);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %.1fs", m_label.c_str(), filled,
                 "##############################", width - filled, "", int(fraction * 100.0),
                 seconds);
    std::fflush(stderr);
}

}  // namespace relief
