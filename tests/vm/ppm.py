# isoterra — QEMU screendumps (binary PPM) for the VM tests' checks:
# ppm(path) -> (width, height, RGB bytes); diff(a, b) -> the mean absolute
# channel difference (255 when the sizes differ).
def ppm(path):
    d = open(path, 'rb').read()
    parts = d.split(maxsplit=4)
    w, h = int(parts[1]), int(parts[2])
    return w, h, parts[4][-w * h * 3:]


def diff(x, y):
    if x[:2] != y[:2]:
        return 255.0
    return sum(abs(p - q) for p, q in zip(x[2], y[2])) / len(x[2])
