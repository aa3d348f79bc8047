# Sourced by the bench scripts. All firmware variants build into one target
# folder (.cargo/config.toml) and each overwrites the same ELF path, so a script
# that measures a variant copies its image away first.
#
# firmware_image NAME CARGO_ARGS...: runs `cargo CARGO_ARGS -q`, copies the ELF to
# <target>/images/NAME/mre-firmware and prints that path.
firmware_image() {
  local name=$1
  shift
  local target=${CARGO_TARGET_DIR:-target}
  cargo "$@" -q >&2
  mkdir -p "$target/images/$name"
  cp "$target/thumbv7em-none-eabihf/firmware/mre-firmware" "$target/images/$name/mre-firmware"
  echo "$target/images/$name/mre-firmware"
}
