# Sourced by the scripts that build a package from Debian's own source
# (scripts/build-trilinos-openmp.sh, perf/lammps_yardstick.sh).
#
# fetch_debian_source PACKAGE WORK: unpacks `apt-get source PACKAGE` into
# WORK unless an unpacked tree is already there, and sets source_dir to it.
# The source comes through a private apt configuration, a deb-src twin of
# the system's debian.sources with its own lists directory: a fresh machine
# has no deb-src entry, and the system's own sources stay as they are.
fetch_debian_source() {
  local package="$1" work="$2"
  mkdir -p "$work/apt/sources.list.d" "$work/apt/lists/partial"
  sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources \
    > "$work/apt/sources.list.d/debian-src.sources"
  local apt_private=(-o "Dir::Etc::SourceList=/dev/null" -o "Dir::Etc::SourceParts=$work/apt/sources.list.d"
                     -o "Dir::State::Lists=$work/apt/lists")
  if ! ls -d "$work/$package"-*/ >/dev/null 2>&1; then
    (cd "$work" && apt-get "${apt_private[@]}" update -qq && apt-get "${apt_private[@]}" source -qq "$package")
  fi
  source_dir="$(ls -d "$work/$package"-*/ | head -n 1)"
}
