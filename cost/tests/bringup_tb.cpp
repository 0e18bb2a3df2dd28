// UART test bench for the FPGA bring-up wrapper (cost/tests/bringup.rs).
// Usage: Vtb IN.bin OUT.bin IN_BYTES OUT_BYTES CYCLES_PER_BIT
// Sends every IN_BYTES-byte record of IN.bin over rx as 8N1 frames (gaps of
// varying length between the bytes of a record), decodes tx on every cycle
// (sampling mid-bit, checking start and stop bits), expects exactly OUT_BYTES
// per record, none while a record is being sent, and writes them to OUT.bin.
// Exit 1 on a framing error, a timeout or an unexpected byte.
#include "Vtop.h"
#include "verilated.h"
#include <cstdio>
#include <cstdlib>
#include <vector>

static Vtop* top;
static unsigned long long cycles = 0;
static int cpb;

// tx decoder, run on every cycle: sampling mid-bit from the falling edge
static std::vector<unsigned char> received;
static int dec_bit = -1;  // -1 idle, 0 start, 1..8 data, 9 stop
static int dec_wait = 0;
static unsigned dec_byte = 0;
static const char* dec_error = nullptr;

static void decode() {
    const int tx = top->tx;
    if (dec_bit < 0) {
        if (!tx) {
            dec_bit = 0;
            dec_wait = cpb / 2;
            dec_byte = 0;
        }
        return;
    }
    if (--dec_wait > 0) return;
    dec_wait = cpb;
    if (dec_bit == 0) {
        if (tx && !dec_error) dec_error = "start bit not low at its middle";
    } else if (dec_bit <= 8) {
        dec_byte |= (unsigned)tx << (dec_bit - 1);
    } else {
        if (!tx && !dec_error) dec_error = "stop bit not high";
        received.push_back((unsigned char)dec_byte);
        dec_bit = -1;
        return;
    }
    dec_bit++;
}

static void tick() {
    top->clk = 0;
    top->eval();
    top->clk = 1;
    top->eval();
    cycles++;
    decode();
}

static void fail(const char* what, size_t record, int byte) {
    std::fprintf(stderr, "uart_tb: %s (record %zu, byte %d, cycle %llu)\n", what, record, byte,
                 cycles);
    std::exit(1);
}

int main(int argc, char** argv) {
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s IN OUT IN_BYTES OUT_BYTES CYCLES_PER_BIT\n", argv[0]);
        return 2;
    }
    const int n_in = std::atoi(argv[3]), n_out = std::atoi(argv[4]);
    cpb = std::atoi(argv[5]);
    FILE* in = std::fopen(argv[1], "rb");
    FILE* out = std::fopen(argv[2], "wb");
    if (!in || !out) {
        std::perror("uart_tb");
        return 2;
    }
    top = new Vtop;
    top->rx = 1;
    top->rst = 1;
    for (int i = 0; i < 4; i++) tick();
    top->rst = 0;
    for (int i = 0; i < 3 * cpb; i++) tick();
    std::vector<unsigned char> rec(n_in);
    size_t r = 0;
    unsigned gap_seed = 1;
    while (std::fread(rec.data(), 1, n_in, in) == (size_t)n_in) {
        for (int k = 0; k < n_in; k++) {
            if (received.size() != r * n_out || dec_bit >= 0)
                fail("tx active while the record is being received", r, k);
            const unsigned frame = 0x200u | ((unsigned)rec[k] << 1);  // stop, data, start
            for (int bit = 0; bit < 10; bit++) {
                top->rx = (frame >> bit) & 1;
                for (int c = 0; c < cpb; c++) tick();
            }
            if (k + 1 < n_in) {
                gap_seed = gap_seed * 1103515245u + 12345u;
                const int gap = (gap_seed >> 16) % (2 * cpb + 1);
                for (int c = 0; c < gap; c++) tick();
            }
        }
        int waited = 0;
        while (received.size() < (r + 1) * n_out || dec_bit >= 0) {
            tick();
            if (dec_error) fail(dec_error, r, (int)(received.size() - r * n_out));
            if (++waited > (12 * n_out + 20) * cpb + 1000) fail("timeout waiting for the answer", r, 0);
        }
        if (received.size() != (r + 1) * n_out) fail("too many bytes in the answer", r, 0);
        r++;
    }
    // nothing more may come out
    for (int c = 0; c < 20 * cpb; c++) {
        tick();
        if (!top->tx) fail("tx active after the last answer", r, 0);
    }
    std::fwrite(received.data(), 1, received.size(), out);
    top->final();
    delete top;
    std::fclose(out);
    std::printf("uart_tb: %zu records, %llu cycles\n", r, cycles);
    return 0;
}
