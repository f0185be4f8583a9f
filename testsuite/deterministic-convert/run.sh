# A conversion is the same bytes on any thread count and at any time (no time stamp in the file).
small=(--theta 4 --phi 4 --ndf 16 --ndf-rows 8 --vndf 16 --data 8 --threads 1 --quiet)
run npf synth -o copper.bsdf --conductor Cu --alpha 0.1,0.3 --wavelengths 450,550,650 "${small[@]}"
settings=(--preset preview --error-pairs 0 --no-predict --quiet)
run npf convert copper.bsdf -o one.exr --threads 1 "${settings[@]}"
# The second on another thread count and another day: libfaketime (Debian's faketime package,
# which scripts/install-deps.sh installs) moves its clock to 2031; without it the note below
# differs from the reference and the case fails.
libfaketime=$(ls /usr/lib/*/faketime/libfaketime.so.1 2> /dev/null | head -n 1)
LD_PRELOAD=$libfaketime FAKETIME="@2031-06-15 12:00:00" date -u +'%Y' > year.txt
note "the second conversion's clock is in year $(cat year.txt)"
LD_PRELOAD=$libfaketime FAKETIME="@2031-06-15 12:00:00" run npf convert copper.bsdf -o two.exr --threads 2 "${settings[@]}"
same one.exr two.exr
run npf synth -o copper2.bsdf --conductor Cu --alpha 0.1,0.3 --wavelengths 450,550,650 "${small[@]}" --threads 2
same copper.bsdf copper2.bsdf
