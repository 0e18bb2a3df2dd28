// A simulated board for `rtl-gen board` (tool/tests/board.rs): the Verilated bring-up wrapper
// with its UART pins driven from a pseudo-terminal, at the bit level.
// Usage: Vpty IN_BYTES OUT_BYTES CYCLES_PER_BIT [corrupt K | silent]
// Prints "pty /dev/pts/N" on stdout, then: every byte the host writes to that terminal goes
// into rx as an 8N1 frame (CYCLES_PER_BIT cycles a bit); tx is decoded on every cycle (mid-bit
// sampling, start and stop bits checked) and every byte goes back to the host. `corrupt K` flips
// bit 0 of the first byte of answer K (a board that computes wrong); `silent` sends nothing.
// The clock runs while a frame goes in or an answer is due, and waits on the terminal
// otherwise. Exits when its stdin closes (the test ended) or on a framing error (status 1).
#include "Vtop.h"
#include "verilated.h"
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

static Vtop* top;
static int cpb;

// tx decoder, as in bringup_tb.cpp
static int dec_bit = -1, dec_wait = 0;
static unsigned dec_byte = 0;

static void fail(const char* what) {
    std::fprintf(stderr, "bringup_pty: %s\n", what);
    std::exit(1);
}

// returns a decoded byte, or -1
static int decode() {
    const int tx = top->tx;
    if (dec_bit < 0) {
        if (!tx) {
            dec_bit = 0;
            dec_wait = cpb / 2;
            dec_byte = 0;
        }
        return -1;
    }
    if (--dec_wait > 0) return -1;
    dec_wait = cpb;
    if (dec_bit == 0) {
        if (tx) fail("start bit not high at its middle");
    } else if (dec_bit <= 8) {
        dec_byte |= (unsigned)tx << (dec_bit - 1);
    } else {
        if (!tx) fail("stop bit not high");
        dec_bit = -1;
        return (int)dec_byte;
    }
    dec_bit++;
    return -1;
}

static int tick() {
    top->clk = 0;
    top->eval();
    top->clk = 1;
    top->eval();
    return decode();
}

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s IN_BYTES OUT_BYTES CYCLES_PER_BIT [corrupt K | silent]\n",
                     argv[0]);
        return 2;
    }
    const long n_in = std::atol(argv[1]), n_out = std::atol(argv[2]);
    cpb = std::atoi(argv[3]);
    long corrupt = -1;
    bool silent = false;
    if (argc >= 6 && !std::strcmp(argv[4], "corrupt")) corrupt = std::atol(argv[5]);
    if (argc >= 5 && !std::strcmp(argv[4], "silent")) silent = true;

    const int master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) || unlockpt(master)) fail("no pseudo-terminal");
    const char* name = ptsname(master);
    // one end held open here: the terminal stays raw, and the host may close and reopen it
    const int slave = open(name, O_RDWR | O_NOCTTY);
    termios t;
    if (slave < 0 || tcgetattr(slave, &t)) fail("cannot open the terminal's other end");
    cfmakeraw(&t);
    tcsetattr(slave, TCSANOW, &t);
    fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);

    top = new Vtop;
    top->rx = 1;
    top->rst = 1;
    for (int i = 0; i < 4; i++) tick();
    top->rst = 0;
    for (int i = 0; i < 3 * cpb; i++) tick();
    std::printf("pty %s\n", name);
    std::fflush(stdout);

    std::deque<unsigned char> to_rx;  // bytes from the host not yet sent into rx
    long in_count = 0;                // bytes of the current record sent into rx
    long due = 0;                     // answer bytes still to come out of tx
    long answers = 0, answer_byte = 0;
    unsigned char buf[4096];
    for (;;) {
        const bool busy = !to_rx.empty() || due > 0 || dec_bit >= 0;
        pollfd fds[2] = {{master, POLLIN, 0}, {0, POLLIN, 0}};
        if (poll(fds, 2, busy ? 0 : 100) < 0 && errno != EINTR) fail("poll");
        if (fds[1].revents) {
            const ssize_t n = read(0, buf, sizeof buf);
            if (n <= 0) break;  // the test closed our stdin: done
        }
        if (fds[0].revents & POLLIN) {
            const ssize_t n = read(master, buf, sizeof buf);
            for (ssize_t i = 0; i < n; i++) to_rx.push_back(buf[i]);
        }
        if (to_rx.empty() && due == 0 && dec_bit < 0) continue;
        // one frame into rx (or a wait for the answer), decoding tx all along
        std::deque<unsigned char> answer;
        if (!to_rx.empty()) {
            const unsigned frame = 0x200u | ((unsigned)to_rx.front() << 1);
            to_rx.pop_front();
            for (int bit = 0; bit < 10; bit++) {
                top->rx = (frame >> bit) & 1;
                for (int c = 0; c < cpb; c++) {
                    const int b = tick();
                    if (b >= 0) answer.push_back((unsigned char)b);
                }
            }
            if (++in_count == n_in) {
                in_count = 0;
                due += n_out;
            }
        } else {
            for (int c = 0; c < 10 * cpb; c++) {
                const int b = tick();
                if (b >= 0) answer.push_back((unsigned char)b);
            }
        }
        for (unsigned char b : answer) {
            if (due == 0) fail("tx sent a byte no record asked for");
            due--;
            if (answers == corrupt && answer_byte == 0) b ^= 1;
            if (++answer_byte == n_out) {
                answer_byte = 0;
                answers++;
            }
            if (!silent && write(master, &b, 1) != 1) fail("writing to the terminal");
        }
    }
    top->final();
    delete top;
    return 0;
}
