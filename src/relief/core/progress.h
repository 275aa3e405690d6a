#pragma once
// A progress bar on stderr, drawn only when stderr is a terminal and not silenced.
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

private:
    void draw(int64_t done);

    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::atomic<int64_t> m_lastDrawMs{-1000};
    bool m_enabled;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace relief
