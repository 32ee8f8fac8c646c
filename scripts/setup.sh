# Shared set-up for the scripts: installs what they need on a fresh machine.
# Sourced, not run.

ensure_rust() {
  # the toolchain is pinned by rust-toolchain.toml; the bare-metal target is not auto-installed
  if ! rustup target list --installed 2>/dev/null | grep -q '^thumbv7em-none-eabihf$'; then
    rustup target add thumbv7em-none-eabihf
  fi
  rustup component list --installed 2>/dev/null | grep -q '^rustfmt' || rustup component add rustfmt
  rustup component list --installed 2>/dev/null | grep -q '^clippy' || rustup component add clippy
}

ensure_qemu() {
  if ! command -v qemu-system-arm >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ]; then
      apt-get update && apt-get install -y qemu-system-arm
    else
      sudo apt-get update && sudo apt-get install -y qemu-system-arm
    fi
  fi
}

ensure_font() {
  # the lab's charts draw their text with DejaVu Sans (ab_glyph, no fontconfig)
  if [ -z "${RIGID3_FONT:-}" ] && [ ! -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ]; then
    if [ "$(id -u)" = 0 ]; then
      apt-get update && apt-get install -y fonts-dejavu-core
    else
      sudo apt-get update && sudo apt-get install -y fonts-dejavu-core
    fi
  fi
}
