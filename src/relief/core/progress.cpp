#include <relief/core/progress.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace relief {

namespace {
std::atomic<bool> gQuiet{false};
constexpr int64_t kBarIntervalMs = 100, kLineIntervalMs = 30000;
}

void Progress::setQuiet(bool quiet) { gQuiet = quiet; }
bool Progress::quiet() { return gQuiet; }

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_mode(gQuiet ? Mode::Off : isatty(STDERR_FILENO) ? Mode::Bar : Mode::Lines),
      m_start(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
    if (m_mode == Mode::Bar) {
        draw(m_total);
        std::fputc('\n', stderr);
    } else if (m_mode == Mode::Lines && m_lastDrawMs.load() >= 0) {  // only after a long run
        drawLine(m_done.load(), std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count());
    }
}

void Progress::advance(int64_t amount) {
    const int64_t done = m_done += amount;
    if (m_mode == Mode::Off) return;
    const int64_t ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::steady_clock::now() - m_start)
                           .count();
    const int64_t interval = m_mode == Mode::Bar ? kBarIntervalMs : kLineIntervalMs;
    int64_t last = m_lastDrawMs.load();
    if (ms - std::max<int64_t>(last, 0) < interval || !m_lastDrawMs.compare_exchange_strong(last, ms)) return;
    m_mode == Mode::Bar ? draw(done) : drawLine(done, double(ms) / 1000.0);
}

void Progress::drawLine(int64_t done, double seconds) {
    std::fprintf(stderr, "%s: %d%% after %.0f s\n", m_label.c_str(), int(100.0 * double(done) / double(m_total)),
                 seconds);
    std::fflush(stderr);
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
