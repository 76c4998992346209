# Sourced by the README's scripts and .ci/run: `stage "what" command...` announces a stage, runs it and says how
# long it took, so a newcomer sees where the minutes go.
stage() {
  local what="$1" start=$SECONDS
  shift
  echo "==> ${what}"
  "$@"
  echo "==> ${what}: done in $((SECONDS - start)) s (${SECONDS} s so far)"
}
