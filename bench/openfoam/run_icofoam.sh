#!/usr/bin/env bash
# OpenFOAM reference for the fluid benchmark: 2-D lid-driven cavity with icoFoam.
#
# Takes OpenFOAM's own icoFoam "cavity" tutorial, refines it to N x N cells
# (default 128 x 128), sets Re = U L / nu = 10 and dt = 0.005 L/U, and runs it
# for STEPS time steps once per entry of NPROCS (default: 1 process, then 2 MPI
# processes). Only icoFoam itself is timed: mesh generation, decomposition,
# reconstruction and sampling happen outside the timed region.
#
# Timing: wall_s is the wall-clock time of the icoFoam command (including the
# mpirun launch for parallel runs), measured with `date +%s.%N` immediately
# before and after it. OpenFOAM's own ExecutionTime/ClockTime from the log are
# printed alongside for reference but are not what goes into the CSV.
#
# Outputs (RESULTS_DIR, default <repo>/bench/results):
#   fluid_openfoam.csv       one row appended per run:
#                            processes,cells,steps,wall_s,cell_steps_per_s
#   openfoam_cavity_u.csv    u/U along the vertical centreline x = L/2, s = y/L
#   openfoam_cavity_v.csv    v/U along the horizontal centreline y = L/2, s = x/L
#                            (both sampled from the final state of the last run,
#                            129 points from wall to wall, columns s,value)
#
# Usage:
#   bench/openfoam/run_icofoam.sh [STEPS]
#     STEPS              number of time steps (default 400, i.e. t = 2 L/U,
#                        which is steady to plotting accuracy at Re = 10)
#   Environment knobs:
#     NPROCS="1 2"       process counts to run, in order (last one is sampled)
#     N=128              cells per side
#     RESULTS_DIR=...    where the CSV files go
#     CHECK_STEADY=1     also run STEPS/2 steps on 1 process (not timed into the
#                        CSV) and print the largest change of the centreline
#                        profiles between t/2 and t
#     KEEP_CASE=1        keep the temporary case directory for inspection
#
# Requires Debian's `openfoam` package (v1912): apt-get install openfoam
set -euo pipefail

# ---------------------------------------------------------------- parameters
STEPS=${1:-400}
N=${N:-128}
NPROCS=${NPROCS:-"1 2"}
CHECK_STEADY=${CHECK_STEADY:-0}
KEEP_CASE=${KEEP_CASE:-0}

# Physical set-up (SI units, as in the tutorial): cavity side L, lid speed U,
# Reynolds number RE; nu and dt follow from them.
L=0.1
U_LID=1
RE=10
NU=$(awk -v u="$U_LID" -v l="$L" -v re="$RE" 'BEGIN { printf "%.10g", u * l / re }')
DT=$(awk -v u="$U_LID" -v l="$L" 'BEGIN { printf "%.10g", 0.005 * l / u }')
CELLS=$((N * N))
NSAMPLE=129          # points per centreline profile, wall to wall

SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO_DIR=$(cd "$SCRIPT_DIR/../.." && pwd)
RESULTS_DIR=${RESULTS_DIR:-$REPO_DIR/bench/results}
mkdir -p "$RESULTS_DIR"
RESULTS_DIR=$(cd "$RESULTS_DIR" && pwd)

if ! [[ "$STEPS" =~ ^[0-9]+$ ]] || [ "$STEPS" -lt 2 ]; then
    echo "STEPS must be an integer >= 2 (got '$STEPS')" >&2
    exit 2
fi

# ------------------------------------------------------- OpenFOAM environment
# Debian's binaries are on PATH already; they only need to know where
# OpenFOAM's etc/ directory is. Sourcing Debian's etc/bashrc works too but is
# noisy (it calls helper scripts the package does not ship), so only the one
# variable that matters is set here.
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -d /usr/share/openfoam/etc ]; then
    export WM_PROJECT_DIR=/usr/share/openfoam
fi
for cmd in blockMesh icoFoam decomposePar reconstructPar postProcess foamDictionary mpirun; do
    command -v "$cmd" >/dev/null || { echo "missing command: $cmd (apt-get install openfoam)" >&2; exit 1; }
done

# Locate the icoFoam cavity tutorial. Debian ships the tutorials in the
# openfoam-examples package under /usr/share/doc; other installs use
# $FOAM_TUTORIALS.
TUTORIAL=""
for dir in \
    "${FOAM_TUTORIALS:-/nonexistent}/incompressible/icoFoam/cavity/cavity" \
    /usr/share/doc/openfoam-examples/examples/incompressible/icoFoam/cavity/cavity \
    /usr/share/openfoam/tutorials/incompressible/icoFoam/cavity/cavity \
    /usr/lib/openfoam/*/tutorials/incompressible/icoFoam/cavity/cavity; do
    if [ -f "$dir/system/blockMeshDict" ] || [ -f "$dir/system/blockMeshDict.gz" ]; then
        TUTORIAL=$dir
        break
    fi
done
if [ -z "$TUTORIAL" ]; then
    echo "icoFoam cavity tutorial not found (is openfoam-examples installed?)" >&2
    exit 1
fi

WORK=$(mktemp -d /tmp/icofoam_cavity.XXXXXX)
cleanup() {
    if [ "$KEEP_CASE" = 1 ]; then echo "case kept in $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT

echo "tutorial : $TUTORIAL"
echo "case     : ${N}x${N} cells, L = $L m, U = $U_LID m/s, Re = $RE (nu = $NU), dt = $DT s"
echo "run      : $STEPS steps (t = $(awk -v s="$STEPS" 'BEGIN { printf "%g", s * 0.005 }') L/U), processes: $NPROCS"

# ------------------------------------------------------------ case set-up
# make_case DIR STEPS: copy the tutorial to DIR, apply the settings above and
# build the mesh.
make_case() {
    local dir=$1 steps=$2
    cp -r "$TUTORIAL" "$dir"
    chmod -R u+w "$dir"
    # Debian may compress files under /usr/share/doc
    find "$dir" -name '*.gz' -exec gunzip -f {} +

    local end_time
    end_time=$(awk -v s="$steps" -v dt="$DT" 'BEGIN { printf "%.10g", s * dt }')

    (
        cd "$dir"
        # Mesh: the tutorial's unit square scaled by L, N x N x 1 cells.
        foamDictionary -entry scale -set "$L" system/blockMeshDict >/dev/null
        foamDictionary -entry blocks \
            -set "( hex (0 1 2 3 4 5 6 7) ($N $N 1) simpleGrading (1 1 1) )" \
            system/blockMeshDict >/dev/null
        # Physics: viscosity for the requested Re, lid velocity U in +x.
        foamDictionary -entry nu -set "$NU" constant/transportProperties >/dev/null
        foamDictionary -entry boundaryField.movingWall.value \
            -set "uniform ($U_LID 0 0)" 0/U >/dev/null
        # Time stepping: fixed dt, write only once at the end (precision kept
        # high enough for the centreline comparison), no re-reading of the
        # dictionaries during the run.
        foamDictionary -entry deltaT            -set "$DT"       system/controlDict >/dev/null
        foamDictionary -entry endTime           -set "$end_time" system/controlDict >/dev/null
        foamDictionary -entry writeControl      -set timeStep    system/controlDict >/dev/null
        foamDictionary -entry writeInterval     -set "$steps"    system/controlDict >/dev/null
        foamDictionary -entry writePrecision    -set 10          system/controlDict >/dev/null
        foamDictionary -entry runTimeModifiable -set false       system/controlDict >/dev/null

        blockMesh > log.blockMesh 2>&1 || { cat log.blockMesh; exit 1; }
    )
}

# write_decompose_dict DIR NP: simple geometric decomposition into NP slabs
# along x (a 2-D case has nothing to split along z).
write_decompose_dict() {
    cat > "$1/system/decomposeParDict" <<EOF
FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      decomposeParDict;
}

numberOfSubdomains $2;
method          simple;
coeffs
{
    n           ($2 1 1);
}
EOF
}

# write_sample_dict DIR: a `sets` function object sampling U along both
# centrelines, 129 evenly spaced points from wall to wall, in the mid-plane of
# the one-cell-thick mesh.
write_sample_dict() {
    local half zmid
    half=$(awk -v l="$L" 'BEGIN { printf "%.10g", l / 2 }')
    zmid=$(awk -v l="$L" 'BEGIN { printf "%.10g", 0.05 * l }')   # mesh is 0.1 L thick
    cat > "$1/system/sampleCentrelines" <<EOF
FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      sampleCentrelines;
}

functions
{
    centrelines
    {
        type                sets;
        libs                ("libsampling.so");
        interpolationScheme cellPoint;
        setFormat           csv;
        fields              (U);
        sets
        (
            vertical
            {
                type    uniform;
                axis    y;
                start   ($half 0 $zmid);
                end     ($half $L $zmid);
                nPoints $NSAMPLE;
            }
            horizontal
            {
                type    uniform;
                axis    x;
                start   (0 $half $zmid);
                end     ($L $half $zmid);
                nPoints $NSAMPLE;
            }
        );
    }
}
EOF
}

# ------------------------------------------------------------------ running
# warn_if_busy: the machine is small (2 cores), so anything else running at
# the same time (a compiler, another benchmark) distorts the timings badly,
# the parallel run most of all. Measure the CPU load over one second just
# before a timed run and warn if more than 10% of the machine was in use.
warn_if_busy() {
    local a b
    a=$(awk '/^cpu / { print $2 + $3 + $4 + $7 + $8 + $9, $5 + $6 }' /proc/stat)
    sleep 1
    b=$(awk '/^cpu / { print $2 + $3 + $4 + $7 + $8 + $9, $5 + $6 }' /proc/stat)
    awk -v a="$a" -v b="$b" 'BEGIN {
        split(a, x, " "); split(b, y, " ")
        busy = y[1] - x[1]; idle = y[2] - x[2]
        if (busy + idle > 0 && busy / (busy + idle) > 0.10)
            printf "WARNING: machine %.0f%% busy before the timed run; timings will be pessimistic\n",
                   100 * busy / (busy + idle) > "/dev/stderr"
    }'
}

# run_solver DIR NP: runs icoFoam on NP processes, sets WALL (seconds).
run_solver() {
    local dir=$1 np=$2 t0 t1
    local -a mpi_flags=()
    if [ "$np" -gt 1 ]; then
        write_decompose_dict "$dir" "$np"
        (cd "$dir" && decomposePar -force > log.decomposePar 2>&1) \
            || { cat "$dir/log.decomposePar"; exit 1; }
        # Open MPI refuses to run as root unless told to, and refuses more
        # ranks than cores unless oversubscription is allowed.
        if [ "$(id -u)" -eq 0 ]; then mpi_flags+=(--allow-run-as-root); fi
        if [ "$np" -gt "$(nproc)" ]; then mpi_flags+=(--oversubscribe); fi
    fi

    warn_if_busy

    # --- timed region: icoFoam only ---
    t0=$(date +%s.%N)
    if [ "$np" -gt 1 ]; then
        (cd "$dir" && mpirun -np "$np" "${mpi_flags[@]}" icoFoam -parallel > log.icoFoam 2>&1)
    else
        (cd "$dir" && icoFoam > log.icoFoam 2>&1)
    fi
    t1=$(date +%s.%N)
    # --- end of timed region ---

    if ! grep -q '^End' "$dir/log.icoFoam"; then
        echo "icoFoam did not finish, see below" >&2
        tail -30 "$dir/log.icoFoam" >&2
        exit 1
    fi
    WALL=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
}

# sample_profiles DIR NP OUT_U OUT_V: samples the final fields of a finished
# run and writes u/U (vertical line) and v/U (horizontal line) against s in
# [0, 1] as CSV.
sample_profiles() {
    local dir=$1 np=$2 out_u=$3 out_v=$4 tdir
    write_sample_dict "$dir"
    (
        cd "$dir"
        if [ "$np" -gt 1 ]; then
            reconstructPar -latestTime > log.reconstructPar 2>&1 || { cat log.reconstructPar; exit 1; }
        fi
        postProcess -dict system/sampleCentrelines -fields '(U)' -latestTime \
            > log.sample 2>&1 || { cat log.sample; exit 1; }
    )
    tdir=$(ls -d "$dir"/postProcessing/centrelines/*/ | sort -V | tail -1)
    # OpenFOAM's csv columns: coordinate, U_0 (= u), U_1 (= v), U_2. The
    # coordinate is printed with only 6 significant digits, so s is rebuilt
    # from the point index (the 129 points are evenly spaced from 0 to L) and
    # checked against the printed coordinate; a point OpenFOAM failed to
    # locate in the mesh would be missing and is caught here.
    to_profile "$tdir/vertical_U.csv"   2 > "$out_u"
    to_profile "$tdir/horizontal_U.csv" 3 > "$out_v"
}

# to_profile FILE COLUMN: s,value lines from an OpenFOAM csv set file, value
# being column COLUMN divided by the lid speed.
to_profile() {
    awk -F, -v l="$L" -v u="$U_LID" -v col="$2" -v f="$1" -v n="$NSAMPLE" '
        NR == 1 { print "s,value"; next }
        {
            s = (NR - 2) / (n - 1)
            d = $1 / l - s; if (d < 0) d = -d
            if (d > 1e-5) { print "unexpected sample point in " f ": " $0 > "/dev/stderr"; exit 1 }
            printf "%.7f,%.8g\n", s, $col / u
        }
        END { if (NR != n + 1) { print "expected " n " points in " f ", got " NR - 1 > "/dev/stderr"; exit 1 } }' "$1"
}

# ------------------------------------------------------------------- main
CSV=$RESULTS_DIR/fluid_openfoam.csv
[ -s "$CSV" ] || echo "processes,cells,steps,wall_s,cell_steps_per_s" > "$CSV"

last_dir="" last_np=""
for np in $NPROCS; do
    dir=$WORK/np$np
    make_case "$dir" "$STEPS"
    run_solver "$dir" "$np"
    rate=$(awk -v c="$CELLS" -v s="$STEPS" -v w="$WALL" 'BEGIN { printf "%.4g", c * s / w }')
    exec_info=$(grep -E '^ExecutionTime' "$dir/log.icoFoam" | tail -1)
    echo "processes=$np cells=$CELLS steps=$STEPS wall_s=$WALL cell_steps_per_s=$rate   (log: $exec_info)"
    echo "$np,$CELLS,$STEPS,$WALL,$rate" >> "$CSV"
    last_dir=$dir last_np=$np
done

sample_profiles "$last_dir" "$last_np" \
    "$RESULTS_DIR/openfoam_cavity_u.csv" "$RESULTS_DIR/openfoam_cavity_v.csv"
echo "profiles : $RESULTS_DIR/openfoam_cavity_u.csv, $RESULTS_DIR/openfoam_cavity_v.csv (from the $last_np-process run)"
echo "results  : $CSV"

# Optional steady-state check: rerun for half the steps on one process and
# compare the centreline profiles with the full-length run.
if [ "$CHECK_STEADY" = 1 ]; then
    half_steps=$((STEPS / 2))
    dir=$WORK/half
    make_case "$dir" "$half_steps"
    run_solver "$dir" 1
    sample_profiles "$dir" 1 "$WORK/half_u.csv" "$WORK/half_v.csv"
    for c in u v; do
        paste -d, "$WORK/half_$c.csv" "$RESULTS_DIR/openfoam_cavity_$c.csv" | awk -F, -v c="$c" '
            NR > 1 { d = $2 - $4; if (d < 0) d = -d; if (d > m) m = d
                     a = $4 < 0 ? -$4 : $4; if (a > r) r = a }
            END { printf "steady check: max |%s(t/2) - %s(t)| = %.3g (max |%s(t)| = %.3g)\n", c, c, m, c, r }'
    done
fi
