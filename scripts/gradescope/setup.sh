#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder's
# image, with the bundle (scripts/gradescope.sh) unzipped in
# /autograder/source. It installs what the students' languages need
# (make, a C and C++ compiler, a JDK, Python: Debian's or Ubuntu's
# packages, only those missing), closes the grader's files to everyone but
# root (a student's program runs as a uid of its own and may read nothing
# of them: not the suite, the references or the binary), and puts
# run_autograder where Gradescope runs it.
set -euo pipefail
cd /autograder/source

need=()
command -v make >/dev/null 2>&1 || need+=(make)
command -v cc >/dev/null 2>&1 || need+=(gcc)
command -v c++ >/dev/null 2>&1 || need+=(g++)
command -v javac >/dev/null 2>&1 || need+=(default-jdk-headless)
command -v python3 >/dev/null 2>&1 || need+=(python3)
if [ "${#need[@]}" -gt 0 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

chown -R root:root /autograder/source
chmod -R go-rwx /autograder/source
install -m 0755 -o root -g root run_autograder /autograder/run_autograder
