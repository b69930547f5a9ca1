#include "terminal.hpp"

#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace nclink::cli {
namespace {

volatile std::sig_atomic_t g_resized = 0;  // set by SIGWINCH

extern "C" void on_winch(int) { g_resized = 1; }

void write_all(const std::string& text) {
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(STDOUT_FILENO, text.data() + done, text.size() - done);
        if (n <= 0) return;
        done += static_cast<std::size_t>(n);
    }
}

}  // namespace

bool FullScreen::is_terminal() { return ::isatty(STDIN_FILENO) != 0 && ::isatty(STDOUT_FILENO) != 0; }

FullScreen::FullScreen() {
    ::tcgetattr(STDIN_FILENO, &saved_);
    termios raw = saved_;
    // No line buffering and no echo; ISIG stays, so Ctrl-C still reaches the
    // interrupt handler and ends the loop in order.
    raw.c_lflag &= static_cast<tcflag_t>(~(ICANON | ECHO));
    raw.c_cc[VMIN] = 0;
    raw.c_cc[VTIME] = 0;
    ::tcsetattr(STDIN_FILENO, TCSANOW, &raw);
    struct sigaction action {};
    action.sa_handler = on_winch;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGWINCH, &action, nullptr);
    // Alternate screen, cursor hidden, home.
    write_all("\x1b[?1049h\x1b[?25l\x1b[H\x1b[2J");
}

FullScreen::~FullScreen() {
    if (restored_) return;
    restored_ = true;
    write_all("\x1b[?25h\x1b[?1049l");
    ::tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
    std::signal(SIGWINCH, SIG_DFL);
}

std::pair<int, int> FullScreen::size() const {
    winsize size{};
    if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0 && size.ws_row > 0) return {size.ws_col, size.ws_row};
    return {80, 24};
}

bool FullScreen::resized() {
    if (!g_resized) return false;
    g_resized = 0;
    return true;
}

Key FullScreen::read_key(std::chrono::milliseconds timeout) {
    pollfd in{STDIN_FILENO, POLLIN, 0};
    if (::poll(&in, 1, static_cast<int>(timeout.count())) <= 0) return Key::none;
    char buffer[16];
    const ssize_t n = ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (n <= 0) return Key::none;
    const std::string keys(buffer, static_cast<std::size_t>(n));
    if (keys[0] == 'q' || keys[0] == 'Q' || keys[0] == 3 /* Ctrl-C without ISIG */) return Key::quit;
    if (keys[0] == 'k' || keys == "\x1b[A" || keys == "\x1bOA") return Key::up;
    if (keys[0] == 'j' || keys == "\x1b[B" || keys == "\x1bOB") return Key::down;
    if (keys == "\x1b[5~" || keys[0] == 'b') return Key::page_up;
    if (keys == "\x1b[6~" || keys[0] == ' ') return Key::page_down;
    if (keys == "\x1b[H" || keys == "\x1b[1~" || keys[0] == 'g') return Key::home;
    return Key::other;
}

void FullScreen::draw(const std::vector<std::string>& lines) {
    std::string frame = "\x1b[H";
    for (std::size_t i = 0; i < lines.size(); ++i) {
        frame += lines[i];
        frame += "\x1b[K";
        if (i + 1 < lines.size()) frame += "\r\n";
    }
    frame += "\x1b[J";
    write_all(frame);
}

}  // namespace nclink::cli
