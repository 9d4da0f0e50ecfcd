# Sourced by every .ci script: prints how long each step and the whole script took, so that a CI log
# says where its minutes went.
ci_script=".ci/$(basename "$0")"
ci_started=$SECONDS
trap 'echo "== ${ci_script}: $((SECONDS - ci_started)) s in all"' EXIT

# step <name> <command...>: runs the command, then prints its time.
step() {
  local name=$1
  shift
  local started=$SECONDS
  echo "== ${ci_script}: ${name}"
  "$@"
  echo "== ${ci_script}: ${name}: $((SECONDS - started)) s"
}
