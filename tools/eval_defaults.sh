# tools/eval_defaults.sh - the settings tools/eval.sh and tools/factorial.sh share,
# sourced by both (`. tools/eval_defaults.sh`); each variable keeps a value already
# in the environment.  Their meaning is documented at the top of tools/eval.sh.
SEEDS=${SEEDS:-8}
LADDER=${LADDER:-16,32,64,128,256,512}
THREADS=${THREADS:-0}
TIME=${TIME:-cpu}
SPECNEE=${SPECNEE:-./specnee}
REUSE=${REUSE:-0}
