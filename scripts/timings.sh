# Sourced by scripts/test and scripts/test_long. With --record-timings they write each part's
# measured time, with the machine and the commit, to a Markdown file that README.md links, so
# that no time in the README is copied there by hand.
timings=()                                    # "| part | result | seconds |" rows
LOAD_AT_START="$(cut -d' ' -f1-3 /proc/loadavg)"

timing_row() {  # timing_row NAME RESULT SECONDS
  timings+=("| $1 | $2 | $3 |")
}

write_timings() {  # write_timings FILE COMMAND TOTAL_SECONDS [LINE...]: the file, each LINE a paragraph
  local file="$1" command="$2" total="$3" commit line
  shift 3
  commit="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  [ -z "$(git status --porcelain --untracked-files=no 2>/dev/null)" ] || commit+=" + local changes"
  {
    echo "# \`$command\`: measured times"
    echo
    echo "Written by \`$command --record-timings\` on $(date -u '+%Y-%m-%d %H:%M UTC'); not edited"
    echo "by hand. Commit $commit, $(nproc) cores, load average $LOAD_AT_START at the start."
    for line in "$@"; do echo; echo "$line"; done
    echo
    echo "| part | result | seconds |"
    echo "|---|---|---:|"
    printf '%s\n' "${timings[@]}"
    echo "| all | | $total |"
  } >"$file"
  echo "wrote $file"
}
