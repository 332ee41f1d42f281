#!/bin/bash
# CPU time (user+sys) of compiling selected library TUs, old (cf8c81a) vs new sources, no ccache.
FLAGS="-DEIGEN_DONT_PARALLELIZE -DIDTO_HAVE_MUJOCO=1 -Didto_EXPORTS -I/work/wt/derivs/build/include -isystem /usr/include/eigen3 -isystem /usr/include/libqhull_r -O3 -DNDEBUG -fPIC -Wall -Wextra -Wpedantic -Wshadow -fno-semantic-interposition -fopenmp -std=c++17"
for tu in multibody/data.cpp multibody/algorithms/kinematics.cpp multibody/algorithms/dynamics.cpp multibody/algorithms/jacobians.cpp multibody/algorithms/rnea_derivatives.cpp contact/contact_engine.cpp solver/trajectory_optimizer.cpp; do
  for ver in old new; do
    if [ $ver = old ]; then root=/tmp/derivs_old; else root=/work/wt/derivs; fi
    [ -f $root/src/$tu ] || { echo "$ver $tu absent"; continue; }
    /usr/bin/time -f "$ver $tu %U user %S sys %e wall" /usr/bin/c++ $FLAGS -I$root/include -o /dev/null -c $root/src/$tu
  done
done
