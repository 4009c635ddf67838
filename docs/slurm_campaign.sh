#!/bin/bash
# A campaign on a Slurm cluster (docs/MPI.md): one rank per specimen group,
# each rank's fits on the cores Slurm gives it. Submit: sbatch docs/slurm_campaign.sh
#SBATCH --job-name=bridgefit-campaign
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=4          # ranks per node
#SBATCH --cpus-per-task=2            # cores per rank: its fit's profile threads
#SBATCH --time=01:00:00
#SBATCH --output=campaign_%j.log
set -euo pipefail
# bridgefit built with -DBRIDGEFIT_MPI=ON against the cluster's MPI; the
# manifest, its records and scenes on a file system every node sees.
MANIFEST=${MANIFEST:-campaign.toml}
OUT=${OUT:-campaign_out}
export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK}
# A rank uses the cores it is bound to (here cpus-per-task); --jobs 1: one
# specimen at a time per rank, its fit's profiles on those cores.
# (--mpi=pmix where the cluster's srun default joins no MPI job: bridgefit
# refuses tasks that MPI does not join rather than run the job N times)
srun --cpu-bind=cores bridgefit campaign "$MANIFEST" --out "$OUT" --jobs 1 --joint
# Open MPI without Slurm's PMI: mpirun -n $SLURM_NTASKS bridgefit campaign ...
