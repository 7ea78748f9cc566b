// A progress bar on stderr, drawn only when stderr is a terminal (DESIGN.md: progress bars on
// anything longer than a few seconds). One line, redrawn in place: "label [#####     ]  45 %".
#pragma once

#include <unistd.h>

#include <cstddef>
#include <iostream>
#include <string>

namespace bimslam::cli {

class ProgressBar {
public:
    explicit ProgressBar(bool enabled = ::isatty(STDERR_FILENO) != 0) : enabled_(enabled) {}
    ~ProgressBar() { Clear(); }

    void Update(const std::string& label, size_t done, size_t total) {
        if (!enabled_ || total == 0) return;
        const int percent = int(100 * done / total);
        if (label == label_ && percent == percent_) return;
        label_ = label;
        percent_ = percent;
        constexpr int kWidth = 30;
        const int filled = percent * kWidth / 100;
        std::string line = "\r" + label.substr(0, 40) +
                           std::string(41 - std::min<size_t>(label.size(), 40), ' ') + "[" +
                           std::string(filled, '#') + std::string(kWidth - filled, ' ') + "] " +
                           std::to_string(percent) + " %";
        std::cerr << line << std::flush;
        drawn_ = true;
    }
    void Clear() {
        if (drawn_) std::cerr << "\r" << std::string(80, ' ') << "\r" << std::flush;
        drawn_ = false;
        label_.clear();
        percent_ = -1;
    }

private:
    bool enabled_;
    bool drawn_ = false;
    std::string label_;
    int percent_ = -1;
};

}  // namespace bimslam::cli
