# trical: the API and the pages on 0.0.0.0:8000, SQLite in the /data volume.

# The Allan sums' compiled loop (setup.py), built in a stage of its own: the image carries the built module
# and no compiler.
FROM python:3.11-slim AS fused
RUN apt-get update \
    && apt-get install -y --no-install-recommends gcc libc6-dev \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /srv/trical
COPY setup.py pyproject.toml README.md ./
COPY app/calibration/noise/allan_fused.pyx ./app/calibration/noise/
RUN pip install --no-cache-dir "setuptools>=77" "Cython>=3.0" \
    && python setup.py build_ext --inplace

FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

WORKDIR /srv/trical

# Dependencies in their own layer: it is rebuilt only when pyproject.toml changes.
COPY pyproject.toml README.md ./
RUN mkdir app && touch app/__init__.py \
    && pip install . \
    && pip uninstall -y trical \
    && rm -rf app build ./*.egg-info

# The code, installed in place so that static/ and templates/ sit beside the package, and the compiled loop.
COPY app ./app
COPY static ./static
COPY templates ./templates
COPY --from=fused /srv/trical/app/calibration/noise/allan_fused.*.so ./app/calibration/noise/
RUN pip install --no-deps -e . \
    && useradd --create-home --uid 10001 trical \
    && mkdir -p /data \
    && chown trical:trical /data

ENV TRICAL_DATABASE_URL=sqlite:////data/trical.db \
    HOST=0.0.0.0 \
    PORT=8000
VOLUME ["/data"]
USER trical
EXPOSE 8000

HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
    CMD ["python", "-c", "import sys, urllib.request; sys.exit(0 if urllib.request.urlopen('http://127.0.0.1:8000/healthz', timeout=2).status == 200 else 1)"]

# No phone's door (--phone-port 0): inside a container the LAN address trical sees is the container's, which no
# phone opens; a phone reaches a container through the operator's TLS proxy (TRICAL_PUBLIC_URL).
CMD ["trical", "serve", "--host", "0.0.0.0", "--port", "8000", "--phone-port", "0"]
