#pragma once
// Progress on stderr unless silenced: a bar redrawn in place on a terminal; elsewhere (logs, CI)
// a plain line every 30 s, so that long work is visible without flooding short runs.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

namespace relief {

class Progress {
public:
    Progress(std::string label, int64_t total);
    ~Progress();
    void advance(int64_t amount = 1);  // thread-safe

    static void setQuiet(bool quiet);
    static bool quiet();  // -q: commands print errors only

private:
    enum class Mode { Off, Bar, Lines };
    void draw(int64_t done);
    void drawLine(int64_t done, double seconds);

    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::atomic<int64_t> m_lastDrawMs{-1000};
    Mode m_mode;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace relief
