# Shared by the bench/ scripts (sourced, not run).

# The median of the numbers on stdin, one a line (the mean of the middle two for an even count).
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# Two measurements taken in turn `pairs` times, so that the machine's drift falls on both alike:
# prints the median of the first, of the second and of their ratio first / second, on one line.
#   pair_medians PAIRS FIRST SECOND [args]: FIRST and SECOND are commands (functions) that are
#   called with the args and print one number.
pair_medians() {
    local pairs=$1 first=$2 second=$3
    shift 3
    local as=() bs=() qs=()
    for _ in $(seq "$pairs"); do
        local a b
        a=$("$first" "$@")
        b=$("$second" "$@")
        as+=("$a") bs+=("$b") qs+=("$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.3f", a / b}')")
    done
    echo "$(printf '%s\n' "${as[@]}" | median) $(printf '%s\n' "${bs[@]}" | median)" \
        "$(printf '%s\n' "${qs[@]}" | median)"
}

# The wall time of a command in seconds (its output thrown away), to the millisecond.
wall() {
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f", b - a}'
}

# Exits with a line when Debian's flam3-render is not installed.
need_flam3() {
    if ! command -v flam3-render >/dev/null; then
        echo "flam3-render not found (apt-get install flam3-utils)" >&2
        exit 1
    fi
}
