# The Blender scripts' report (check_assets.py, check_gltf.py): a line per
# check, "ok" or "FAIL", and the failures kept for the exit status.
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)
    return ok
