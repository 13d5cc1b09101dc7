"""One compute thread for torch (Keras' backend here) and OpenMP: the networks of these tests are
small, and on a busy machine (`make test` runs two suites beside the rostests) a second thread
spinning for a core the other processes hold made the Keras tests ten times slower."""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
