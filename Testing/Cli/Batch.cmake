# tissuemosaic batch (issue 55, docs/BATCH.md): a local batch stopped and resumed, a real Slurm job array, and bad
# manifests refused with a clear message before any row runs. Included by CMakeLists.txt (${cli}, ${work}, ${expect}).
set(batch_work ${CMAKE_CURRENT_BINARY_DIR}/batch)

# Four studies (one a corrupt video), --jobs 2, SIGTERM half way, run again: only the rest; models byte-identical to
# reconstruct alone. About 40 s of CPU on 2 cores.
add_test(NAME cli.batch.local COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/batch-local.sh ${cli} ${batch_work}/local)
set_tests_properties(cli.batch.local PROPERTIES LABELS "cli;batch" TIMEOUT 600)

# The same studies as a Slurm job array on daemons the test starts; a skip (77) only where they cannot start, a
# failure there too with TM_REQUIRE_SLURM=1 (.ci/run). RUN_SERIAL: its tasks are real processes that the
# controller starts, and it must not wait behind a loaded machine's other tests for its time limit.
add_test(NAME cli.batch.slurm COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/batch-slurm.sh ${cli} ${batch_work}/slurm)
set_tests_properties(cli.batch.slurm PROPERTIES LABELS "cli;batch;slurm" TIMEOUT 900 SKIP_RETURN_CODE 77
                     RUN_SERIAL TRUE)

# tm_batch_failure(NAME STATUS REGEX MANIFEST_TEXT [BATCH_OPTIONS...]): writes the manifest (printf format) and
# expects `tissuemosaic batch` on it to exit STATUS with stderr matching REGEX, having run no row.
function(tm_batch_failure name status regex text)
  set(folder ${batch_work}/bad_${name})
  set(extension csv)
  if(text MATCHES "^studies:")
    set(extension yml)
  endif()
  add_test(NAME cli.batch.bad.${name}
           COMMAND sh -c "d=$1 t=$2 e=$3 x=$4 r=$5 c=$6; shift 6; rm -rf \"$d\" && mkdir -p \"$d\" && printf \"$t\" > \"$d/manifest.$e\" && \"$x\" \"$r\" \"$c\" batch \"$d/manifest.$e\" \"$@\" && ! test -e \"$d/runs\""
                   ${name} ${folder} "${text}" ${extension} ${expect} "${regex}" ${cli} ${ARGN})
  set_tests_properties(cli.batch.bad.${name} PROPERTIES LABELS "cli;batch" ENVIRONMENT EXPECT_STATUS=${status})
endfunction()
set(good_args "--left-frames l --right-frames r --focal-px 300 --baseline-mm 5")
add_test(NAME cli.batch.bad.no_manifest
         COMMAND ${expect} "cannot read manifest '.*/nothing.csv': no such file" ${cli} batch ${batch_work}/nothing.csv)
set_tests_properties(cli.batch.bad.no_manifest PROPERTIES LABELS "cli;batch" ENVIRONMENT EXPECT_STATUS=1)
tm_batch_failure(missing_column 1 "manifest '.*' line 1: the column 'out' is missing"
                 "name,args\\na,\"${good_args}\"\\n")
tm_batch_failure(unknown_column 1 "manifest '.*' line 1: unknown column 'argz' \\(columns: name, out, args"
                 "name,out,argz\\na,runs/a,x\\n")
tm_batch_failure(unclosed_quote 1 "manifest '.*' line 3: a quoted field is never closed"
                 "name,out,args\\na,runs/a,\"${good_args}\"\\nb,runs/b,\"--video v.mp4\\n")
tm_batch_failure(field_count 1 "manifest '.*' line 2: 2 fields, but the header has 3 \\(name,out,args\\)"
                 "name,out,args\\na,runs/a\\n")
tm_batch_failure(header_only 1 "manifest '.*' has no study" "name,out,args\\n")
tm_batch_failure(duplicate_name 1 "line 3 \\(row 2\\): the name 'a' is given to an earlier row too"
                 "name,out,args\\na,runs/a,\"${good_args}\"\\na,runs/b,\"${good_args}\"\\n")
tm_batch_failure(bad_args 2 "manifest row 2 \\(b\\): unknown option --vidoe \\(did you mean --video\\?\\)"
                 "name,out,args\\na,runs/a,\"${good_args}\"\\nb,runs/b,\"--vidoe v.mp4 --focal-px 300 --baseline-mm 5\"\\n")
tm_batch_failure(bad_number 2 "manifest row 1 \\(a\\): option --fps expects a number, got 'fast'"
                 "name,out,args\\na,runs/a,\"${good_args} --fps fast\"\\n")
tm_batch_failure(out_in_args 2 "manifest row 1 \\(a\\): --out is set by the batch"
                 "name,out,args\\na,runs/a,\"${good_args} --out m.ply\"\\n")
tm_batch_failure(row_out_of_range 2 "--row 3: the manifest '.*' has rows 1 to 1"
                 "name,out,args\\na,runs/a,\"${good_args}\"\\n" --row 3)
tm_batch_failure(slurm_option_alone 2 "--partition applies to --slurm and --slurm-script-only"
                 "name,out,args\\na,runs/a,\"${good_args}\"\\n" --partition gpu)
tm_batch_failure(yaml_missing_key 1 "manifest '.*' line 2: the key 'out' is missing"
                 "studies:\\n  - name: a\\n    args: ${good_args}\\n")

# The sbatch script of a YAML manifest, written and not submitted: the array's rows, the options passed through,
# a GPU for the row that asks for CUDA, and each task running its row. (No ';' in the command: CheckOutput.cmake
# would split it there.)
tm_output_test(NAME cli.batch.slurm_script
               MATCH "wrote .*/a.sbatch: a job array of 3 tasks \\(rows 1-3\\).*#SBATCH --array=1-3%2.#SBATCH --output=.*/slurm_script/m-slurm/slurm-%A_%a.out.#SBATCH --chdir=.*/slurm_script.#SBATCH --ntasks=1.#SBATCH --partition=gpu.#SBATCH --time=1:00:00.#SBATCH --mem=8G.#SBATCH --gres=gpu:1.exec '.*/tissuemosaic' batch '.*/slurm_script/m.yml' --row \"[$]SLURM_ARRAY_TASK_ID\""
               COMMAND sh -c "rm -rf \"$2\" && mkdir -p \"$2\" && printf 'studies:\\n  - {name: a, out: runs/a, args: \"--left-frames l --right-frames r --focal-px 300 --baseline-mm 5\"}\\n  - name: b\\n    out: runs/b\\n    args: --video v.mp4 --calib rig.yml\\n    device: cuda\\n  - {name: c, out: runs/c, args: --video w.mp4 --calib rig.yml, params: fast.yml}\\n' > \"$2/m.yml\" && \"$1\" batch \"$2/m.yml\" --slurm-script-only \"$2/a.sbatch\" --partition gpu --time 1:00:00 --mem 8G --max-running 2 && cat \"$2/a.sbatch\" && ! test -e \"$2/runs\""
                       slurm_script ${cli} ${batch_work}/slurm_script)
set_tests_properties(cli.batch.slurm_script PROPERTIES LABELS "cli;batch")

# A manifest as a spreadsheet saves it: a byte-order mark, CRLF line ends, a quoted field with doubled quotes around
# a path with a space, a field without quotes. Read, every row's options parsed, the script written.
tm_output_test(NAME cli.batch.spreadsheet_csv
               MATCH "wrote .*/a.sbatch: a job array of 2 tasks \\(rows 1-2\\)"
               COMMAND sh -c "rm -rf \"$2\" && mkdir -p \"$2\" && printf '\\357\\273\\277name,out,args\\r\\nclip one,runs/a,\"--video \"\"my clip.mp4\"\" --focal-px 300 --baseline-mm 5\"\\r\\nb,runs/b,--video v.mp4 --focal-px 300 --baseline-mm 5\\r\\n' > \"$2/m.csv\" && \"$1\" batch \"$2/m.csv\" --slurm-script-only \"$2/a.sbatch\""
                       spreadsheet ${cli} ${batch_work}/spreadsheet)
set_tests_properties(cli.batch.spreadsheet_csv PROPERTIES LABELS "cli;batch")
