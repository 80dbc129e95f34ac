"""The study's entry point (study/__main__.py): every command in its name table answers --help
with exit 0 (its module imports, with study/common.py, and its options parse), no arguments and
an unknown command exit 2 naming the commands, and a command's errors name the command.
Usage: commands_test.py"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True
STUDY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, STUDY)
import importlib.util  # noqa: E402

spec = importlib.util.spec_from_file_location("study_main", os.path.join(STUDY, "__main__.py"))
entry = importlib.util.module_from_spec(spec)
spec.loader.exec_module(entry)


def study(*args):
    return subprocess.run([sys.executable, STUDY, *args], capture_output=True, text=True)


def main():
    for command in entry.COMMANDS:
        if command == "sweep-provenance":
            r = study(command)
            assert r.returncode != 0 and "usage: study sweep-provenance" in r.stderr, r.stderr
            continue
        r = study(command, "--help")
        assert r.returncode == 0, f"{command} --help: {r.returncode}\n{r.stderr}"
        assert "usage" in r.stdout.lower(), f"{command} --help printed no usage:\n{r.stdout}"
    r = study()
    assert r.returncode == 2 and "bench" in r.stdout, r
    r = study("no-such-command")
    assert r.returncode == 2 and "unknown command 'no-such-command'" in r.stderr, r.stderr
    r = study("bench", "--no-such-flag")
    assert r.returncode == 2 and "study bench" in r.stderr, r.stderr
    # -m study from the repository's root is the same entry point
    r = subprocess.run([sys.executable, "-m", "study", "--help"], capture_output=True, text=True,
                       cwd=os.path.join(STUDY, ".."))
    assert r.returncode == 0 and "keys" in r.stdout, r
    print(f"commands_test: ok, {len(entry.COMMANDS)} commands")


if __name__ == "__main__":
    main()
