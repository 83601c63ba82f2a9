import numpy as np

LANES: int

def sums_of_share(x: np.ndarray, ms: np.ndarray, share: int, shares: int, out: np.ndarray) -> None: ...
