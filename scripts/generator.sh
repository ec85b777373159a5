# shellcheck shell=bash
# Sourced by scripts/build.sh and scripts/configure-sanitize.sh: a build folder not yet
# configured is generated for Ninja when ninja is installed and CMAKE_GENERATOR is not set
# (a clean release build on 2 cores: 5.0 min with Ninja, 5.6 min with Make, one after the
# other); a configured folder keeps the generator it has, since CMake refuses to change it.
fvx_choose_generator() {
  if [ ! -f "$1/CMakeCache.txt" ] && [ -z "${CMAKE_GENERATOR:-}" ] && command -v ninja >/dev/null; then
    export CMAKE_GENERATOR=Ninja
  fi
}
