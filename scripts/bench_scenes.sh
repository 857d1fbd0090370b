# Sourced by the read and pack benchmarks (bash): makes their two scenes in
# the current directory with the build `$after`, and sets `scenes`:
#   hamlet256  `vox voxelize demo:hamlet --res 256`
#   mesh1024   `vox voxelize $mesh --res 1024` (surface), when $mesh exists
# Needs: after, mesh, threads.
"$after" voxelize demo:hamlet --res 256 -o hamlet256.vdb --quiet
scenes="hamlet256"
if [ -f "$mesh" ]; then
  "$after" voxelize "$mesh" --res 1024 -o mesh1024.vdb --quiet --threads "$threads"
  scenes="$scenes mesh1024"
fi
