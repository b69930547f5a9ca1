// A full-screen session on the terminal for `nclink top`: the alternate
// screen, no echo, keys read one at a time, the size and its changes
// (SIGWINCH). Plain ANSI/VT100 sequences, which every terminal emulator and
// tmux understand; no curses needed for one table. Everything is restored
// when the session ends (also after Ctrl-C, which the caller turns into an
// orderly exit).
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <termios.h>
#include <vector>

namespace nclink::cli {

enum class Key { none, quit, up, down, page_up, page_down, home, other };

class FullScreen {
public:
    /// Takes over stdin/stdout; both must be terminals (is_terminal()).
    FullScreen();
    ~FullScreen();  ///< restores the screen, the cursor and the terminal modes
    FullScreen(const FullScreen&) = delete;
    FullScreen& operator=(const FullScreen&) = delete;

    static bool is_terminal();

    /// Columns and rows now.
    std::pair<int, int> size() const;
    /// True once after the terminal was resized.
    bool resized();
    /// Waits up to `timeout` for a key.
    Key read_key(std::chrono::milliseconds timeout);
    /// Draws `lines` from the top-left corner in one write, each line cleared
    /// to its end, so nothing flickers and nothing scrolls.
    void draw(const std::vector<std::string>& lines);

private:
    termios saved_{};
    bool restored_ = false;
};

}  // namespace nclink::cli
