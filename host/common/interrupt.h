// SIGINT and SIGTERM during a render (docs/RENDERER.md, "Output"): the first one asks the render
// to stop after the pass in flight, which then writes the image of its completed passes and
// exits 130 (SIGINT) or 143 (SIGTERM); a second one ends the process at once, removing the file
// being written (its temporary, never the target). Outside a render the default actions hold.
#pragma once

namespace hrpp {

// Installs the handlers; the destructor restores the previous ones. One at a time.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

// The first signal received while an InterruptScope was in force (SIGINT, SIGTERM), or 0.
int interrupt_signal();

// The temporary file being written now, which a second signal removes (nullptr: none). The
// path is copied; at most 4095 bytes are kept.
void set_file_being_written(const char* path);

// Thrown by a command that stopped on a signal once its outputs are written: main() returns
// 128 + signal.
struct Interrupted {
  int signal = 0;
};

}  // namespace hrpp
