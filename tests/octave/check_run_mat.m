% Checks that run.mat, written by `ipmc-swim run --format mat`, holds the
% numbers of the run's CSV files (sim/runs/output.h, RunResultTree): every
% time-series column, every state (metres in states.csv, millimetres in
% run.mat), the per-cycle table and the summary's mean speed. Numbers are
% compared to within 4 eps relative: Octave's dlmread and the program's
% strtod may round a 10-digit decimal differently by one unit in the last
% place. Prints one line and exits 0 if they match; errors otherwise.
function check_run_mat(dir)
  s = load(fullfile(dir, 'run.mat'));
  run = s.run;
  check_table(run.timeseries, fullfile(dir, 'timeseries.csv'), 1);
  check_table(run.states, fullfile(dir, 'states.csv'), 1e3);
  summary = fileread(fullfile(dir, 'summary.json'));
  speed = regexp(summary, '"mean_speed_along_mm_s": ([^,\n]+)', 'tokens'){1}{1};
  expect_close(run.summary.mean_speed_along_mm_s, str2double(speed), 'mean_speed_along_mm_s');
  if ~strcmp(run.summary.controller, 'pid')
    error('summary.controller is %s, not pid', run.summary.controller);
  end
  if numel(run.cycles.com_along_mm) ~= numel(run.cycles.cycle)
    error('cycles: com_along_mm and cycle differ in length');
  end
  printf('octave: run.mat equals timeseries.csv (%d columns x %d samples) and states.csv\n', ...
         numel(fieldnames(run.timeseries)), numel(run.timeseries.time_s));
end

% Every column of the CSV `path` against the field of the same name in
% `fields`; a column in metres (`_m`) is `<name>m` times `metres_scale`.
function check_table(fields, path, metres_scale)
  fid = fopen(path);
  header = strsplit(fgetl(fid), ',');
  fclose(fid);
  data = dlmread(path, ',', 1, 0);
  for k = 1:numel(header)
    name = header{k};
    scale = 1;
    if numel(name) > 2 && strcmp(name(end-1:end), '_m')
      name = [name 'm'];
      scale = metres_scale;
    end
    if ~isfield(fields, name)
      error('%s: column %s is not in run.mat', path, name);
    end
    expect_close(fields.(name), scale * data(:, k), [path ': ' name]);
  end
end

function expect_close(got, want, what)
  got = got(:);
  want = want(:);
  if numel(got) ~= numel(want)
    error('%s: %d values in run.mat, %d in the CSV', what, numel(got), numel(want));
  end
  tolerance = 4 * eps * max(abs(want), realmin);
  bad = find(abs(got - want) > tolerance, 1);
  if ~isempty(bad)
    error('%s: value %d is %.17g in run.mat, %.17g in the CSV', what, bad, got(bad), want(bad));
  end
end
