// Generic Verilator harness for every unit that rtl-gen emits.
//
// Compiled once per design by the `sim` crate (sim/src/harness.rs) together
// with the design's Verilog and a generated `ports.inc`, which describes the
// top module's ports as X-macros:
//
//   #define RTL_TOP_NAME "mulcmp"     // top module name, for messages
//   #define RTL_LATENCY 3             // cycles from in_valid to out_valid
//   #define RTL_CLK clk               // handshake port names
//   #define RTL_RST rst
//   #define RTL_IN_VALID in_valid
//   #define RTL_OUT_VALID out_valid
//   #define RTL_INPUTS(X) X(a, 16) X(b, 16)    // data inputs, record order
//   #define RTL_OUTPUTS(X) X(lt, 1) X(eq, 1)   // data outputs, record order
//   #define RTL_IN_READY in_ready              // valid/ready units only
//   #define RTL_OUT_READY out_ready
//
// A valid/ready unit (docs/handshake.md) is driven with random stalls on
// both sides by default: idle cycles before a transaction and out_ready low,
// each with --stall-percent chance (30). A transaction is held until
// in_ready takes it; a result counts when out_valid and out_ready are high,
// and must hold (out_valid and data) while out_ready is low. With
// --stall-percent 0 the consumer never stalls and the unit must keep the
// declared latency and take a transaction every cycle (in_ready high).
//
// The model class is always `Vdut` (verilator --prefix Vdut), so nothing here
// depends on the design. Streams use the `rtlvec 1` binary format described
// in docs/vectors.md. Usage: see usage() below.
//
// Exit codes: 0 success; 2 bad usage or bad input stream; 3 the design broke
// the handshake (latency check); 4 I/O error on the output or a VCD file.

#include "Vdut.h"
#include "ports.inc"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

#include <cerrno>
#include <csignal>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

constexpr int EXIT_USAGE = 2;
constexpr int EXIT_PROTOCOL = 3;
constexpr int EXIT_IO = 4;

// Reset is held for this many cycles before the first transaction; two would
// do for any synchronous reset, the margin costs nothing.
constexpr uint64_t RESET_CYCLES = 4;
// After the last transaction, this many idle cycles beyond the latency are
// clocked so that a spurious late out_valid is still caught.
constexpr uint64_t DRAIN_EXTRA = 4;
// A valid/ready unit that takes no transaction, or delivers no result, for
// this many cycles (beyond its latency) is stuck.
constexpr uint64_t STUCK_CYCLES = 100000;
// I/O block size: large blocks keep syscalls far off the per-vector path.
constexpr size_t BLOCK = size_t(1) << 20;
// Headers are short; a longer "line" means this is not an rtlvec stream.
constexpr size_t MAX_HEADER = 64 * 1024;

// Record sizes: every port takes ceil(width / 8) little-endian bytes.
#define RTL_BYTES(RTL_P, RTL_W) +((RTL_W) + 7) / 8
constexpr size_t IN_BYTES = 0 RTL_INPUTS(RTL_BYTES);
constexpr size_t OUT_BYTES = 0 RTL_OUTPUTS(RTL_BYTES);
#undef RTL_BYTES

static_assert(RTL_LATENCY >= 0, "latency must be non-negative");

[[noreturn]] void die(int code, const char* fmt, ...) {
    std::fprintf(stderr, "harness(%s): ", RTL_TOP_NAME);
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    va_end(ap);
    std::fputc('\n', stderr);
    std::exit(code);
}

// Mask of the low `width` bits; width is 1..=64 (checked by the sim crate).
constexpr uint64_t mask_of(unsigned width) {
    return width >= 64 ? ~uint64_t(0) : (uint64_t(1) << width) - 1;
}

// Little-endian load/store of `n` bytes; `n` is a compile-time constant at
// every call site, so the compiler unrolls these into plain loads and stores.
inline uint64_t load_le(const uint8_t* p, unsigned n) {
    uint64_t v = 0;
    for (unsigned i = 0; i < n; ++i) v |= uint64_t(p[i]) << (8 * i);
    return v;
}

inline void store_le(uint8_t* p, uint64_t v, unsigned n) {
    for (unsigned i = 0; i < n; ++i) p[i] = uint8_t(v >> (8 * i));
}

std::string header_of(const char* const* names, const unsigned* widths, size_t n) {
    std::string h = "rtlvec 1 ";
    for (size_t i = 0; i < n; ++i) {
        if (i) h += ',';
        h += names[i];
        h += ':';
        h += std::to_string(widths[i]);
    }
    return h;
}

#define RTL_NAME(RTL_P, RTL_W) #RTL_P,
#define RTL_WIDTH(RTL_P, RTL_W) (RTL_W),
const char* const IN_NAMES[] = {RTL_INPUTS(RTL_NAME)};
const unsigned IN_WIDTHS[] = {RTL_INPUTS(RTL_WIDTH)};
const char* const OUT_NAMES[] = {RTL_OUTPUTS(RTL_NAME)};
const unsigned OUT_WIDTHS[] = {RTL_OUTPUTS(RTL_WIDTH)};
#undef RTL_NAME
#undef RTL_WIDTH
constexpr size_t N_IN = sizeof(IN_WIDTHS) / sizeof(IN_WIDTHS[0]);
constexpr size_t N_OUT = sizeof(OUT_WIDTHS) / sizeof(OUT_WIDTHS[0]);

// Buffered reader over a file descriptor, handing out whole records.
class Input {
  public:
    Input(int fd, std::string name) : fd_(fd), name_(std::move(name)), buf_(BLOCK) {}

    const std::string& name() const { return name_; }

    // Reads the header line (without '\n'); dies if there is none.
    std::string header() {
        std::string line;
        for (;;) {
            if (pos_ == len_ && !fill()) {
                die(EXIT_USAGE, "%s: %s", name_.c_str(),
                    line.empty() ? "empty input: expected an 'rtlvec 1 ...' header line"
                                 : "input ends inside the header line (no newline)");
            }
            const uint8_t* start = buf_.data() + pos_;
            const void* nl = std::memchr(start, '\n', len_ - pos_);
            size_t take = nl ? size_t(static_cast<const uint8_t*>(nl) - start) : len_ - pos_;
            line.append(reinterpret_cast<const char*>(start), take);
            pos_ += take;
            if (line.size() > MAX_HEADER) {
                die(EXIT_USAGE, "%s: no header line within the first %zu bytes: not an rtlvec stream",
                    name_.c_str(), MAX_HEADER);
            }
            if (nl) {
                ++pos_;
                return line;
            }
        }
    }

    // Returns a pointer to the next `n` bytes, or nullptr at a clean end of
    // input. Dies on a partial record at the end.
    const uint8_t* next(size_t n, uint64_t record) {
        if (len_ - pos_ < n) {
            compact();
            while (len_ < n && fill()) {
            }
            if (len_ == 0) return nullptr;
            if (len_ < n) {
                die(EXIT_USAGE, "%s: record %llu (byte offset %llu) is truncated: %zu of %zu bytes",
                    name_.c_str(), (unsigned long long)record, (unsigned long long)(consumed_ + pos_),
                    len_, n);
            }
        }
        const uint8_t* p = buf_.data() + pos_;
        pos_ += n;
        return p;
    }

    uint64_t offset_of(const uint8_t* p) const { return consumed_ + uint64_t(p - buf_.data()); }

  private:
    void compact() {
        if (pos_ == 0) return;
        std::memmove(buf_.data(), buf_.data() + pos_, len_ - pos_);
        consumed_ += pos_;
        len_ -= pos_;
        pos_ = 0;
    }

    // Appends one read's worth of data; false at end of input.
    bool fill() {
        if (pos_ == len_) {
            consumed_ += pos_;
            pos_ = len_ = 0;
        }
        if (len_ == BLOCK) compact();
        for (;;) {
            ssize_t r = ::read(fd_, buf_.data() + len_, BLOCK - len_);
            if (r > 0) {
                len_ += size_t(r);
                return true;
            }
            if (r == 0) return false;
            if (errno != EINTR) die(EXIT_IO, "%s: read failed: %s", name_.c_str(), std::strerror(errno));
        }
    }

    int fd_;
    std::string name_;
    std::vector<uint8_t> buf_;
    size_t pos_ = 0;
    size_t len_ = 0;
    uint64_t consumed_ = 0;  // stream offset of buf_[0]
};

class Output {
  public:
    Output(int fd, std::string name) : fd_(fd), name_(std::move(name)), buf_(BLOCK) {}
    ~Output() { flush(); }

    void put(const void* data, size_t n) {
        if (len_ + n > BLOCK) flush();
        std::memcpy(buf_.data() + len_, data, n);
        len_ += n;
    }

    // Space for one record; caller advances with commit().
    uint8_t* reserve(size_t n) {
        if (len_ + n > BLOCK) flush();
        return buf_.data() + len_;
    }
    void commit(size_t n) { len_ += n; }

    void flush() {
        size_t off = 0;
        while (off < len_) {
            ssize_t w = ::write(fd_, buf_.data() + off, len_ - off);
            if (w > 0) {
                off += size_t(w);
            } else if (w < 0 && errno != EINTR) {
                len_ = 0;  // do not retry from the destructor
                die(EXIT_IO, "%s: write failed: %s", name_.c_str(), std::strerror(errno));
            }
        }
        len_ = 0;
    }

  private:
    int fd_;
    std::string name_;
    std::vector<uint8_t> buf_;
    size_t len_ = 0;
};

// splitmix64: tiny, well-mixed, and reproducible across platforms.
struct Rng {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
};

void usage(FILE* f) {
    std::fprintf(f,
                 "usage: rtl_harness [--in FILE] [--out FILE] [--vcd FILE] [--bubbles SEED]\n"
                 "                   [--bubble-percent P] [--stalls SEED] [--stall-percent P]\n"
                 "Simulates %s (latency %u): reads 'rtlvec 1' input records (stdin by default),\n"
                 "drives one per cycle with in_valid=1, writes one output record per out_valid\n"
                 "cycle (stdout by default) and checks out_valid against the declared latency.\n"
                 "  --vcd FILE          trace every signal to FILE\n"
                 "  --bubbles SEED      insert pseudo-random idle cycles (random data, in_valid=0)\n"
                 "  --bubble-percent P  chance of an idle cycle before each transaction (default 30)\n"
                 "  --stalls SEED       valid/ready units: seed of the random stalls (default 1)\n"
                 "  --stall-percent P   valid/ready units: chance of an idle input cycle and of\n"
                 "                      out_ready low (default 30; 0: never stalled, full rate)\n"
                 "Prints 'cycles=N transactions=M bubbles=B stalls=S' on stderr at the end.\n"
                 "Exit: 0 ok, 2 usage or input error, 3 latency/handshake violation, 4 I/O error.\n",
                 RTL_TOP_NAME, unsigned(RTL_LATENCY));
}

uint64_t parse_u64(const char* opt, const char* s) {
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(s, &end, 0);
    if (errno || end == s || *end || s[0] == '-') die(EXIT_USAGE, "%s: not an unsigned number: '%s'", opt, s);
    return uint64_t(v);
}

}  // namespace

int main(int argc, char** argv) {
    // A closed output pipe must surface as a write error (exit 4), not a
    // silent SIGPIPE death the caller cannot explain.
    std::signal(SIGPIPE, SIG_IGN);

    const char* in_path = nullptr;
    const char* out_path = nullptr;
    const char* vcd_path = nullptr;
    bool bubbles = false;
    uint64_t bubble_seed = 0;
    uint64_t bubble_percent = 30;
    uint64_t stall_seed = 1;
    uint64_t stall_percent = 30;
    bool stall_option = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&](const char* opt) -> const char* {
            if (i + 1 >= argc) die(EXIT_USAGE, "%s needs a value (see --help)", opt);
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            usage(stdout);
            return 0;
        } else if (a == "--in") {
            in_path = value("--in");
        } else if (a == "--out") {
            out_path = value("--out");
        } else if (a == "--vcd") {
            vcd_path = value("--vcd");
        } else if (a == "--bubbles") {
            bubbles = true;
            bubble_seed = parse_u64("--bubbles", value("--bubbles"));
        } else if (a == "--bubble-percent") {
            bubble_percent = parse_u64("--bubble-percent", value("--bubble-percent"));
            if (bubble_percent > 95) die(EXIT_USAGE, "--bubble-percent must be at most 95");
        } else if (a == "--stalls") {
            stall_seed = parse_u64("--stalls", value("--stalls"));
            stall_option = true;
        } else if (a == "--stall-percent") {
            stall_percent = parse_u64("--stall-percent", value("--stall-percent"));
            if (stall_percent > 95) die(EXIT_USAGE, "--stall-percent must be at most 95");
            stall_option = true;
        } else if (a.rfind("+verilator+", 0) == 0) {
            // Verilator's own runtime options are passed through below.
        } else {
            usage(stderr);
            die(EXIT_USAGE, "unknown argument '%s'", a.c_str());
        }
    }

    int in_fd = 0;
    std::string in_name = "stdin";
    if (in_path) {
        in_fd = ::open(in_path, O_RDONLY);
        if (in_fd < 0) die(EXIT_USAGE, "cannot open input %s: %s", in_path, std::strerror(errno));
        in_name = in_path;
    }
    int out_fd = 1;
    std::string out_name = "stdout";
    if (out_path) {
        out_fd = ::open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out_fd < 0) die(EXIT_IO, "cannot create output %s: %s", out_path, std::strerror(errno));
        out_name = out_path;
    }
#ifdef F_SETPIPE_SZ
    // Bigger pipes mean fewer context switches between the vector generator,
    // this process and the checker; failure (not a pipe, limit) is harmless.
    ::fcntl(in_fd, F_SETPIPE_SZ, int(BLOCK));
    ::fcntl(out_fd, F_SETPIPE_SZ, int(BLOCK));
#endif

    Input in(in_fd, in_name);
    Output out(out_fd, out_name);

    const std::string want_in = header_of(IN_NAMES, IN_WIDTHS, N_IN);
    const std::string got_in = in.header();
    if (got_in != want_in) {
        if (got_in.rfind("rtlvec ", 0) != 0) {
            die(EXIT_USAGE, "%s: not an rtlvec stream: header line must start with 'rtlvec 1 ' (got '%.80s')",
                in.name().c_str(), got_in.c_str());
        }
        die(EXIT_USAGE,
            "%s: header does not match the inputs this harness was built for\n"
            "  expected: %s\n"
            "  got:      %s",
            in.name().c_str(), want_in.c_str(), got_in.c_str());
    }
    const std::string out_header = header_of(OUT_NAMES, OUT_WIDTHS, N_OUT) + "\n";
    out.put(out_header.data(), out_header.size());

    auto contextp = std::make_unique<VerilatedContext>();
    contextp->commandArgs(argc, argv);
    auto top = std::make_unique<Vdut>(contextp.get(), "dut");

#if VM_TRACE
    std::unique_ptr<VerilatedVcdC> tfp;
    if (vcd_path) {
        contextp->traceEverOn(true);
        tfp = std::make_unique<VerilatedVcdC>();
        top->trace(tfp.get(), 99);
        tfp->open(vcd_path);
        if (!tfp->isOpen()) die(EXIT_IO, "cannot open VCD file %s", vcd_path);
    }
#else
    if (vcd_path) die(EXIT_USAGE, "--vcd: this harness was built without --trace");
#endif

    // In-flight transactions: ring[c & ring_mask] holds 1 + the index of the
    // transaction presented at cycle c, or 0 for an idle cycle. A power of two
    // keeps the per-cycle index a mask instead of a division.
    uint64_t ring_size = 1;
    while (ring_size < uint64_t(RTL_LATENCY) + 1) ring_size <<= 1;
    const uint64_t ring_mask = ring_size - 1;
    std::vector<uint64_t> ring(ring_size, 0);

    uint64_t cycle = 0;  // absolute cycle number, reset cycles included
    uint64_t transactions = 0;
    uint64_t outputs = 0;
    uint64_t bubble_cycles = 0;
    uint64_t stall_cycles = 0;
    Rng rng{bubble_seed};

    // A handshake violation keeps everything produced so far: the results
    // before the failing cycle and a VCD that ends at it, for debugging.
    char msg[512];
    auto violation = [&]() {
        out.flush();
#if VM_TRACE
        if (tfp) tfp->close();
#endif
        die(EXIT_PROTOCOL, "%s", msg);
    };

    // The transaction presented at cycle - latency (1 + its index), or 0.
    auto due_now = [&]() -> uint64_t {
        return cycle >= uint64_t(RTL_LATENCY) ? ring[(cycle - RTL_LATENCY) & ring_mask] : 0;
    };
    // out_valid must be high exactly when a transaction is due.
    auto check_latency = [&](bool out_valid) {
        const uint64_t due = due_now();
        if (out_valid == (due != 0)) return;
        if (out_valid) {
            std::snprintf(msg, sizeof msg,
                          "cycle %llu: out_valid=1 but no transaction was presented at cycle "
                          "%lld (declared latency %u)",
                          (unsigned long long)cycle, (long long)cycle - (long long)RTL_LATENCY,
                          unsigned(RTL_LATENCY));
        } else {
            std::snprintf(msg, sizeof msg,
                          "cycle %llu: out_valid=0 but transaction %llu, presented at cycle %llu, "
                          "is due (declared latency %u)",
                          (unsigned long long)cycle, (unsigned long long)(due - 1),
                          (unsigned long long)(cycle - RTL_LATENCY), unsigned(RTL_LATENCY));
        }
        violation();
    };
    // The data outputs of this cycle as one record.
    auto store_outputs = [&](uint8_t* p) {
#define RTL_STORE(RTL_P, RTL_W)                            \
    store_le(p, uint64_t(top->RTL_P), ((RTL_W) + 7) / 8); \
    p += ((RTL_W) + 7) / 8;
        RTL_OUTPUTS(RTL_STORE)
#undef RTL_STORE
    };
    auto edge = [&]() {
        top->RTL_CLK = 1;
        top->eval();
#if VM_TRACE
        if (tfp) tfp->dump(cycle * 10 + 5);
#endif
        ++cycle;
    };
    // Settle with clk low and trace: inputs are already set.
    auto settle = [&]() {
        top->RTL_CLK = 0;
        top->eval();
#if VM_TRACE
        if (tfp) tfp->dump(cycle * 10);
#endif
    };
    auto reset_out_valid = [&](bool out_valid) {
        // Cycle 0 precedes the first reset edge, so its out_valid is still
        // the power-up value.
        if (out_valid && cycle > 0) {
            std::snprintf(msg, sizeof msg, "cycle %llu: out_valid=1 while rst=1 (after the first reset edge)",
                          (unsigned long long)cycle);
            violation();
        }
    };

    // Idle cycles carry random data so that a unit which samples its inputs
    // when in_valid=0 produces visibly different results.
    auto idle_inputs = [&]() {
#define RTL_RANDOM(RTL_P, RTL_W) top->RTL_P = rng.next() & mask_of(RTL_W);
        RTL_INPUTS(RTL_RANDOM)
#undef RTL_RANDOM
    };
    // Drives record `rec` onto the data inputs.
    auto load_record = [&](const uint8_t* rec) {
        const uint8_t* p = rec;
#define RTL_LOAD(RTL_P, RTL_W)                                                             \
    {                                                                                     \
        const uint64_t v = load_le(p, ((RTL_W) + 7) / 8);                                 \
        if (v & ~mask_of(RTL_W)) {                                                        \
            die(EXIT_USAGE,                                                               \
                "%s: record %llu (byte offset %llu), field %s: value 0x%llx wider than "  \
                "port (%u bits)",                                                         \
                in.name().c_str(), (unsigned long long)transactions,                      \
                (unsigned long long)in.offset_of(rec), #RTL_P, (unsigned long long)v,     \
                unsigned(RTL_W));                                                         \
        }                                                                                 \
        top->RTL_P = v;                                                                   \
        p += ((RTL_W) + 7) / 8;                                                           \
    }
        RTL_INPUTS(RTL_LOAD)
#undef RTL_LOAD
    };

    top->RTL_RST = 1;
#define RTL_ZERO(RTL_P, RTL_W) top->RTL_P = 0;
    RTL_INPUTS(RTL_ZERO)
#undef RTL_ZERO

#ifdef RTL_IN_READY
    // valid/ready: transactions are taken when in_ready is high, results
    // when out_ready is; see the file header.
    Rng stall_rng{stall_seed};
    const bool never_stalled = stall_percent == 0;
    auto stall = [&]() { return !never_stalled && stall_rng.next() % 100 < stall_percent; };
    bool held = false;  // last cycle showed a result that out_ready did not take
    uint8_t shown[OUT_BYTES];
    uint8_t now[OUT_BYTES];
    // One cycle with in_valid = valid and out_ready drawn; true when the
    // unit took the transaction.
    auto cycle_ready = [&](bool valid, bool in_reset) -> bool {
        const bool ready = !in_reset && !stall();
        top->RTL_IN_VALID = valid;
        top->RTL_OUT_READY = ready;
        settle();
        const bool out_valid = top->RTL_OUT_VALID;
        const bool taken = valid && !in_reset && top->RTL_IN_READY;
        if (in_reset) {
            reset_out_valid(out_valid);
            edge();
            return false;
        }
        stall_cycles += !ready;
        if (taken) ++transactions;
        store_outputs(now);
        if (held && !out_valid) {
            std::snprintf(msg, sizeof msg, "cycle %llu: out_valid fell while the result waited for out_ready",
                          (unsigned long long)cycle);
            violation();
        }
        if (held && std::memcmp(shown, now, OUT_BYTES) != 0) {
            std::snprintf(msg, sizeof msg, "cycle %llu: the outputs changed while out_valid waited for out_ready",
                          (unsigned long long)cycle);
            violation();
        }
        if (out_valid && outputs >= transactions) {
            std::snprintf(msg, sizeof msg,
                          "cycle %llu: out_valid=1 but all %llu transactions taken have been delivered",
                          (unsigned long long)cycle, (unsigned long long)transactions);
            violation();
        }
        if (never_stalled) {
            ring[cycle & ring_mask] = taken ? transactions : 0;
            check_latency(out_valid);
            if (valid && !taken) {
                std::snprintf(msg, sizeof msg,
                              "cycle %llu: in_ready=0 although out_ready was always high (fewer than "
                              "one transaction per cycle)",
                              (unsigned long long)cycle);
                violation();
            }
        }
        held = out_valid && !ready;
        if (held) std::memcpy(shown, now, OUT_BYTES);
        if (out_valid && ready) {
            out.put(now, OUT_BYTES);
            ++outputs;
        }
        edge();
        return taken;
    };

    for (uint64_t i = 0; i < RESET_CYCLES; ++i) cycle_ready(false, true);
    top->RTL_RST = 0;
    for (;;) {
        const uint8_t* rec = in.next(IN_BYTES, transactions);
        if (!rec) break;
        while (stall() || (bubbles && rng.next() % 100 < bubble_percent)) {
            idle_inputs();
            cycle_ready(false, false);
            ++bubble_cycles;
        }
        load_record(rec);
        for (uint64_t waited = 0; !cycle_ready(true, false); ++waited) {
            if (waited > STUCK_CYCLES + RTL_LATENCY) {
                std::snprintf(msg, sizeof msg, "cycle %llu: in_ready stayed low for %llu cycles (transaction %llu)",
                              (unsigned long long)cycle, (unsigned long long)waited,
                              (unsigned long long)transactions);
                violation();
            }
        }
    }
    for (uint64_t quiet = 0; outputs < transactions;) {
        const uint64_t before = outputs;
        idle_inputs();
        cycle_ready(false, false);
        quiet = outputs == before ? quiet + 1 : 0;
        if (quiet > STUCK_CYCLES + RTL_LATENCY) {
            std::snprintf(msg, sizeof msg, "cycle %llu: transaction %llu never came out",
                          (unsigned long long)cycle, (unsigned long long)outputs);
            violation();
        }
    }
    for (uint64_t i = 0; i < DRAIN_EXTRA; ++i) {
        idle_inputs();
        cycle_ready(false, false);
    }
#else
    if (stall_option) die(EXIT_USAGE, "--stalls, --stall-percent: %s has no out_ready (handshake=valid)", RTL_TOP_NAME);
    (void)stall_seed;
    (void)stall_percent;
    // One clock cycle: sample (so latency-0 units are seen combinationally),
    // check out_valid against the latency, then the rising edge.
    auto clock = [&](uint64_t tag, bool in_reset) {
        top->RTL_IN_VALID = tag != 0;
        settle();
        ring[cycle & ring_mask] = tag;
        const bool out_valid = top->RTL_OUT_VALID;
        if (in_reset) {
            reset_out_valid(out_valid);
        } else {
            check_latency(out_valid);
            if (out_valid) {
                store_outputs(out.reserve(OUT_BYTES));
                out.commit(OUT_BYTES);
                ++outputs;
            }
        }
        edge();
    };

    for (uint64_t i = 0; i < RESET_CYCLES; ++i) clock(0, true);
    top->RTL_RST = 0;

    for (;;) {
        const uint8_t* rec = in.next(IN_BYTES, transactions);
        if (!rec) break;
        if (bubbles) {
            while (rng.next() % 100 < bubble_percent) {
                idle_inputs();
                clock(0, false);
                ++bubble_cycles;
            }
        }
        load_record(rec);
        ++transactions;
        clock(transactions, false);
    }

    for (uint64_t i = 0; i < uint64_t(RTL_LATENCY) + DRAIN_EXTRA; ++i) {
        idle_inputs();
        clock(0, false);
    }
#endif
    out.flush();
    if (outputs != transactions) {
        // Unreachable when the latency check passed; kept as a last guard.
        std::snprintf(msg, sizeof msg, "%llu transactions but %llu results",
                      (unsigned long long)transactions, (unsigned long long)outputs);
        violation();
    }

    top->final();
#if VM_TRACE
    if (tfp) tfp->close();
#endif
    std::fprintf(stderr, "cycles=%llu transactions=%llu bubbles=%llu stalls=%llu\n", (unsigned long long)cycle,
                 (unsigned long long)transactions, (unsigned long long)bubble_cycles,
                 (unsigned long long)stall_cycles);
    return 0;
}
