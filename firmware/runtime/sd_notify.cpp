// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/runtime/sd_notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace bimslam::runtime {

SdNotifier::SdNotifier() {
    const char* socket_path = std::getenv("NOTIFY_SOCKET");
    if (socket_path == nullptr || socket_path[0] == '\0') return;
    address_ = socket_path;
    if (address_.size() >= sizeof(sockaddr_un{}.sun_path)) return;
    if (const char* usec = std::getenv("WATCHDOG_USEC")) {
        watchdog_ns_ = std::atoll(usec) * 1000;
        // WATCHDOG_PID, when set, names the process that should send (sd_watchdog_enabled).
        if (const char* pid = std::getenv("WATCHDOG_PID")) {
            if (std::atoll(pid) != getpid()) watchdog_ns_ = 0;
        }
    }
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
}

SdNotifier::~SdNotifier() {
    if (fd_ >= 0) ::close(fd_);
}

bool SdNotifier::Notify(const std::string& state) {
    if (fd_ < 0) return false;
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::memcpy(a.sun_path, address_.data(), address_.size());
    if (a.sun_path[0] == '@') a.sun_path[0] = '\0';  // abstract namespace
    const socklen_t length = socklen_t(offsetof(sockaddr_un, sun_path) + address_.size());
    return ::sendto(fd_, state.data(), state.size(), MSG_NOSIGNAL,
                    reinterpret_cast<const sockaddr*>(&a), length) == ssize_t(state.size());
}

}  // namespace bimslam::runtime
