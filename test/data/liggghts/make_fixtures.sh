#!/bin/sh
# Regenerate the LIGGGHTS fixtures with Debian's liggghts (3.8.0).
cd "$(dirname "$0")" && liggghts -in make_fixtures.in -log none -echo none -screen none
