# Bad input gets one line naming the file and the problem, exit 1, and no output file.
: > empty.bsdf
printf 'not a material\n' > text.exr
printf 'BRDF\x02\x00\x00\x00' > short.bsdf
head -c 100 /dev/zero > zeros.binary
mkdir folder.bsdf
for f in missing.bsdf empty.bsdf text.exr short.bsdf zeros.binary folder.bsdf; do
    run npf info "$f"
done
run npf convert empty.bsdf -o out.exr
[[ -e out.exr ]] && note "out.exr was written" || note "no out.exr"
run npf synth -o no-such-folder/m.bsdf --diffuse 0.5 --quiet
